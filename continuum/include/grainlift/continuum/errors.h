// Errors raised by the continuum engine. Non-convergence is not an error: it is
// reported in ContinuumOutput::converged / ContinuumOutput::message. An exception inside the
// solve (a bug, a failed factorisation, memory) is: solve_flow() throws SolverError.
#pragma once

#include <stdexcept>
#include <string>

namespace grainlift::continuum {

/// @brief A ContinuumConfig value is out of range or inconsistent (names the field).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// @brief The solve failed with an exception (not a non-convergence): what() is
/// "continuum solver failed: " and the original message. Thrown by solve_flow() on every rank
/// that failed together; a failure of one rank alone ends all ranks instead (MpiSession).
struct SolverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// @brief The solve ran out of memory, or would have: the direct solve's estimate (MUMPS's
/// analysis) does not fit in what the process may still take, or an allocation failed
/// (std::bad_alloc). what() is one sentence with the need and the limit, without the ways out
/// (the caller knows the case's keys). Thrown by solve_flow() like SolverError.
struct OutOfMemory : SolverError {
  using SolverError::SolverError;
};

}  // namespace grainlift::continuum
