// Independent replicas of one case (same physics, one bed and seed each) pooled into one
// result whose standard errors come from the spread between the replicas.
#pragma once

#include <vector>

#include "grainlift/shared/run_result.h"

namespace grainlift {

/// @brief Pool the results of N >= 1 replicas into one.
///
/// Means of drag, lift, torque and contacts: the plain mean over replicas, standard error
/// SD / sqrt(N) of the replicas' means (absent for N = 1: then the replica's own block
/// error is kept); samples: the sum; blocks: N. Surface stresses, contact histograms and
/// fields: the mean over replicas at each angle, bin and cell (fields over the replicas where
/// the cell is finite), surface standard errors from the spread. The force series, lid and
/// far-field series, geometry and the other diagnostics are those of the first replica.
/// Diagnostics series replica_drag, replica_lift, replica_torque hold each replica's means.
/// @throws std::invalid_argument for no replicas or replicas of different grids.
RunResult pool_replicas(const std::vector<RunResult>& replicas);

}  // namespace grainlift
