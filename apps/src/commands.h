// The subcommands of `grainlift` (run, validate, compare, sweep, calibrate, report, keys,
// schema).
#pragma once

#include <string>
#include <vector>

#include "grainlift/shared/run/run_driver.h"

namespace grainlift::app {

/// Arguments of `grainlift calibrate`.
struct CalibrateArgs {
  std::string case_path, out;
  std::vector<std::string> sets;
  double pressure = 0;                    ///< Pa; 0: the case's
  std::vector<double> inertial_numbers;   ///< empty: the default sweep
  double strain_scale = 1;
  int threads = 1;
  bool quiet = false;
  /// DEM results (folders or dem.h5) of the case whose wall law is fitted into the file's
  /// [wall] table (scripts/fit_wall.py); empty: no [wall]
  std::vector<std::string> wall_runs;
  /// Measure the nonlocal fluidity's cooperativity amplitude A on a creeping layer (with the
  /// mu_s of the rheology file at out, which must exist) into its [nonlocal] table, instead of
  /// the mu(I) sweep
  bool nonlocal = false;
  int seeds = 4;  ///< independent beds of the creeping-layer cell (--nonlocal)
  double creep_inertial_number = 0.05;  ///< nominal I of the creeping-layer cell's sheared top
};

/// `grainlift calibrate` (calibrate_command.cc); exit code.
int cmd_calibrate(const CalibrateArgs& a);

/// `grainlift report DIR` (report_command.cc): runs scripts/report.py on a result folder, which
/// writes DIR/report.html; exit code. A folder without dem.h5 or fem.h5 is an InputError.
int cmd_report(const std::string& dir);

/// `grainlift schema [--markdown]` (schema_command.cc): prints the output file's schema table,
/// as the Markdown of docs/schema.md with @p markdown; exit code.
int cmd_schema(bool markdown);

/// `grainlift export lammps CASE DIR` (lammps_command.cc): the case's bed and scene as a
/// LAMMPS input in DIR; exit code.
int cmd_export_lammps(const std::string& case_path, const std::vector<std::string>& sets,
                      const std::string& dir);
/// `grainlift import lammps DIR --out OUT`: LAMMPS's outputs in DIR as OUT/dem.h5 and
/// summary.json; exit code.
int cmd_import_lammps(const std::string& dir, const std::string& out);

/// Parses argv, runs the subcommand, maps errors to exit codes (0, 1 run failed, 2 bad input).
int main_with_args(int argc, char** argv);

/// The solvers compiled into this binary (solver_table.cc).
std::vector<SolverEntry> available_solvers();
/// Loads what @p picked need before the first of them runs (the continuum's module and MPI),
/// so that no solver's time includes it, and returns them; throws RunError when the module
/// cannot be loaded.
std::vector<SolverEntry> start_solvers(std::vector<SolverEntry> picked);

/// @p o's threads and replicas for `run` and `sweep`, and whether both solvers run at once
/// (RunOptions::side_by_side): where there are cores for both (@p threads >= 2), with one
/// replica (replicas share out the threads themselves), on one process (under mpirun every
/// rank solves the continuum).
void set_threads(RunOptions& o, int threads, int replicas);

/// Rank and number of processes of an MPI run (0 and 1 without MPI; solver_table.cc).
int process_rank();
int process_count();
/// Under mpirun, for an exception that reached a command: true when every rank got one there
/// with the same exit code; otherwise prints @p what with the rank and ends every rank with
/// MPI_Abort(@p code) (see continuum::MpiSession::all_ranks_failed). True without MPI.
bool failed_on_every_rank(const std::string& what, int code);

}  // namespace grainlift::app
