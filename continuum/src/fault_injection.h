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

/// @brief Test hook, not a feature: throws std::bad_alloc, as an allocation that fails would,
/// when the environment variable GRAINLIFT_TEST_BAD_ALLOC_AT_LEVEL equals @p level (the nested
/// level about to be solved). Test: MachineFaultsRun (tests/scripts).
void bad_alloc_here_if_requested(int level);

/// @brief Test hook, not a feature: how long a failing rank waits for the others
/// (MpiSession::all_ranks_failed): the environment variable GRAINLIFT_TEST_FAILURE_WAIT_SECONDS
/// when it holds a number in (0, @p usual], else @p usual. Lets the one-rank failure test
/// (FemMpi.FailureOnOneRankEndsEveryRank) wait 1 s instead of 10, while the other rank spins in
/// a collective call.
double failure_wait_seconds(double usual);

}  // namespace grainlift::continuum::internal
