// The continuum module's entry point (fem_module.h): the solver entry and the MPI session,
// behind plain function pointers.
#include "grainlift/continuum/fem_module.h"

#include <memory>

#include "grainlift/continuum/continuum_solver.h"
#include "grainlift/continuum/mpi_session.h"

namespace grainlift::continuum {
namespace {

std::unique_ptr<MpiSession>& session() {
  static std::unique_ptr<MpiSession> s;
  return s;
}

void start_mpi(int* argc, char*** argv) {
  if (session()) return;
  static int no_argc = 0;
  static char* no_argv_storage[] = {nullptr};
  static char** no_argv = no_argv_storage;
  session() = std::make_unique<MpiSession>(argc ? *argc : no_argc, argv ? *argv : no_argv);
}

void end_mpi() { session().reset(); }

int rank() { return MpiSession::rank(); }
int size() { return MpiSession::size(); }

bool all_ranks_failed(const std::string& message, int exit_code) {
  return MpiSession::all_ranks_failed(MpiSession::FailureSite::command, message, exit_code);
}

}  // namespace
}  // namespace grainlift::continuum

extern "C" const grainlift::continuum::FemModule* grainlift_fem_module() {
  namespace gc = grainlift::continuum;
  static const gc::FemModule m = [] {
    gc::FemModule f;
    f.solver_entry = &gc::solver_entry;
    f.start_mpi = &gc::start_mpi;
    f.end_mpi = &gc::end_mpi;
    f.rank = &gc::rank;
    f.size = &gc::size;
    f.all_ranks_failed = &gc::all_ranks_failed;
    return f;
  }();
  return &m;
}
