// grainlift: the command line. Parses arguments and hands the work to the modules; no physics.
#include "commands.h"

#ifdef GRAINLIFT_HAVE_FEM
#include <cstdio>
#include <exception>
#include <string>

#include "fem_module_loader.h"
#include "grainlift/shared/errors.h"
#endif

int main(int argc, char** argv) {
#ifdef GRAINLIFT_HAVE_FEM
  // Under an MPI launcher every rank enters MPI (the continuum's Trilinos solvers) at start,
  // whatever it runs; otherwise the continuum module and MPI start with the first continuum
  // run (fem_module_loader.h: about 0.9 s that DEM runs and the other commands do not pay).
  if (argc > 1 && (std::string(argv[1]) == "run" || std::string(argv[1]) == "sweep") &&
      grainlift::app::started_by_mpi_launcher()) {
    try {
      grainlift::app::fem_module().start_mpi(&argc, &argv);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "grainlift: run failed: %s\n", e.what());
      return grainlift::exit_run_failed;
    }
  }
#endif
  const int code = grainlift::app::main_with_args(argc, argv);
#ifdef GRAINLIFT_HAVE_FEM
  if (const auto* m = grainlift::app::fem_module_if_loaded()) m->end_mpi();
#endif
  return code;
}
