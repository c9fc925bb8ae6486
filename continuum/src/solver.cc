// solve_flow(): validates the configuration, runs the cylinder problem (CylinderProblem,
// cylinder_problem.h) and turns an exception into a SolverError after the MPI ranks have
// agreed on it. validate_config() is in config_validation.cc.
#include "grainlift/continuum/solver.h"

#include <exception>
#include <new>
#include <string>

#include "cylinder_problem.h"
#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/mpi_session.h"

namespace grainlift::continuum {

ContinuumOutput solve_flow(const ContinuumConfig& c,
                           const std::function<void(const std::string&)>& log) {
  validate_config(c);
  try {
    return internal::CylinderProblem(c, log).run();
  } catch (const ConfigError&) {
    throw;
  } catch (const OutOfMemory& e) {
    MpiSession::all_ranks_failed(MpiSession::FailureSite::continuum_solve, e.what(), 1);
    throw;
  } catch (const std::bad_alloc&) {
    const std::string message =
        "an allocation failed (std::bad_alloc)";
    MpiSession::all_ranks_failed(MpiSession::FailureSite::continuum_solve, message, 1);
    throw OutOfMemory(message);
  } catch (const std::exception& e) {
    const std::string message = std::string("continuum solver failed: ") + e.what();
    // on several ranks, a failure of this rank alone ends the run here (the others would wait
    // for it in their next collective call); one of all ranks together is reported as usual
    MpiSession::all_ranks_failed(MpiSession::FailureSite::continuum_solve, message, 1);
    throw SolverError(message);
  }
}

}  // namespace grainlift::continuum
