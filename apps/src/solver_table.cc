// Which solvers this build has. Each module contributes one SolverEntry.
#include "commands.h"

#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/dem_solver.h"
#endif
#ifdef GRAINLIFT_HAVE_FEM
#include "grainlift/continuum/continuum_solver.h"
#include "grainlift/continuum/mpi_session.h"
#endif

namespace grainlift::app {

std::vector<SolverEntry> available_solvers() {
  std::vector<SolverEntry> s;
#ifdef GRAINLIFT_HAVE_DEM
  s.push_back(dem::solver_entry());
#endif
#ifdef GRAINLIFT_HAVE_FEM
  s.push_back(continuum::solver_entry());
#endif
  return s;
}

int process_rank() {
#ifdef GRAINLIFT_HAVE_FEM
  return continuum::MpiSession::rank();
#else
  return 0;
#endif
}

int process_count() {
#ifdef GRAINLIFT_HAVE_FEM
  return continuum::MpiSession::size();
#else
  return 1;
#endif
}

bool failed_on_every_rank(const std::string& what, int code) {
#ifdef GRAINLIFT_HAVE_FEM
  return continuum::MpiSession::all_ranks_failed(continuum::MpiSession::FailureSite::command,
                                                 what, code);
#else
  (void)what;
  (void)code;
  return true;
#endif
}

}  // namespace grainlift::app
