// Internal: fault injection for the tests. deal.II-free.
#pragma once

#include <string>

namespace grainlift::continuum::internal {

/// @brief Test hook, not a feature: when the environment variable GRAINLIFT_TEST_FAIL_ON_RANK
/// equals this process's MPI rank, throws std::runtime_error
/// "GRAINLIFT_TEST_FAIL_ON_RANK=R: test failure @p where", as a bad_alloc or a failed
/// factorisation on that rank alone would. Does nothing otherwise. The cylinder problem calls it
/// just before the nonlinear solve (tests: FemMpi.FailureOnOneRankEndsEveryRank, where the other
/// rank goes on into the solve's collective calls, and ContinuumCylinder's exception test).
/// @param where  the place, for the message (e.g. "before the nonlinear solve")
void fail_here_if_requested(const std::string& where);

}  // namespace grainlift::continuum::internal
