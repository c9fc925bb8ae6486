// grainlift: the command line. Parses arguments and hands the work to the modules; no physics.
#include "commands.h"

#ifdef GRAINLIFT_HAVE_FEM
#include <memory>
#include <string>

#include "grainlift/continuum/mpi_session.h"
#endif

int main(int argc, char** argv) {
#ifdef GRAINLIFT_HAVE_FEM
  // MPI (needed by the continuum's Trilinos solvers) for the whole process, finalised on
  // return; only for the commands that solve (MPI start-up costs a noticeable fraction of a
  // second, e.g. for `grainlift keys`)
  std::unique_ptr<grainlift::continuum::MpiSession> mpi;
  if (argc > 1 && (std::string(argv[1]) == "run" || std::string(argv[1]) == "sweep"))
    mpi = std::make_unique<grainlift::continuum::MpiSession>(argc, argv);
#endif
  return grainlift::app::main_with_args(argc, argv);
}
