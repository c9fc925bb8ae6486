// The continuum as a module that the `grainlift` command loads when a run needs it.
//
// deal.II pulls in about 200 shared libraries (Trilinos, PETSc, OpenCASCADE, ...), and the
// dynamic linker spends about 0.6 s binding them at every start; MPI's start-up adds 0.3 s.
// A DEM run, `validate`, `report` or `--version` needs neither, so the command is linked
// without the continuum and dlopen()s this module on the first continuum run (or at start
// under an MPI launcher, where every rank must take part in MPI from the beginning).
// deal.II-free: the command includes it.
#pragma once

#include <string>

#include "grainlift/shared/run/run_driver.h"

namespace grainlift::continuum {

/// Changed whenever FemModule changes: a module of another version is refused by name.
inline constexpr int kFemModuleVersion = 1;

/// The "fem" solver's one-line description (its SolverEntry, in the module and in the command).
inline constexpr const char* kFemSolverDescription =
    "finite-element mu(I) continuum (deal.II, Taylor-Hood Q2-Q1)";

/// What the module gives the command: the "fem" solver entry and the process's MPI session.
struct FemModule {
  int version = kFemModuleVersion;
  /// The "fem" entry of the solver table (continuum_solver.h).
  SolverEntry (*solver_entry)() = nullptr;
  /// Starts MPI for the rest of the process unless it runs already (MpiSession); argc and argv
  /// as main() received them, or null when MPI starts in the middle of a command.
  void (*start_mpi)(int* argc, char*** argv) = nullptr;
  /// Ends the session start_mpi() began (MPI_Finalize); nothing when none was begun.
  void (*end_mpi)() = nullptr;
  /// MpiSession::rank(), size(), and all_ranks_failed() at the command's failure site.
  int (*rank)() = nullptr;
  int (*size)() = nullptr;
  bool (*all_ranks_failed)(const std::string& message, int exit_code) = nullptr;
};

}  // namespace grainlift::continuum

/// The module's one exported entry point (the command looks it up by this name).
extern "C" const grainlift::continuum::FemModule* grainlift_fem_module();
