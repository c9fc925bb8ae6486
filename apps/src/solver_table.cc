// Which solvers this build has. Each module contributes one SolverEntry; the continuum's is
// loaded on its first run (fem_module_loader.h).
#include "commands.h"

#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/dem_solver.h"
#endif
#ifdef GRAINLIFT_HAVE_FEM
#include "fem_module_loader.h"
#endif

namespace grainlift::app {

std::vector<SolverEntry> available_solvers() {
  std::vector<SolverEntry> s;
#ifdef GRAINLIFT_HAVE_DEM
  s.push_back(dem::solver_entry());
#endif
#ifdef GRAINLIFT_HAVE_FEM
  SolverEntry fem;
  fem.name = "fem";
  fem.description = continuum::kFemSolverDescription;
  fem.run = [](const Case& c, const RunOptions& opt, ProgressReporter& progress) {
    const continuum::FemModule& m = fem_module();
    m.start_mpi(nullptr, nullptr);  // normally done already (start_solvers, main.cc)
    return m.solver_entry().run(c, opt, progress);
  };
  s.push_back(std::move(fem));
#endif
  return s;
}

std::vector<SolverEntry> start_solvers(std::vector<SolverEntry> picked) {
#ifdef GRAINLIFT_HAVE_FEM
  for (const SolverEntry& e : picked)
    if (e.name == "fem") fem_module().start_mpi(nullptr, nullptr);
#endif
  return picked;
}

int process_rank() {
#ifdef GRAINLIFT_HAVE_FEM
  if (const continuum::FemModule* m = fem_module_if_loaded()) return m->rank();
#endif
  return 0;
}

int process_count() {
#ifdef GRAINLIFT_HAVE_FEM
  if (const continuum::FemModule* m = fem_module_if_loaded()) return m->size();
#endif
  return 1;
}

void set_threads(RunOptions& o, int threads, int replicas) {
  o.threads = threads;
  o.replicas = replicas;
  o.side_by_side = threads >= 2 && replicas == 1 && process_count() == 1;
}

bool failed_on_every_rank(const std::string& what, int code) {
#ifdef GRAINLIFT_HAVE_FEM
  if (const continuum::FemModule* m = fem_module_if_loaded())
    return m->all_ranks_failed(what, code);
#endif
  (void)what;
  (void)code;
  return true;
}

}  // namespace grainlift::app
