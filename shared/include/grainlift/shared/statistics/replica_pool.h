// Independent replicas of one case (same physics, one bed and seed each) pooled into one
// result by the pooling rule of statistics.h (pooled_mean).
#pragma once

#include <vector>

#include "grainlift/shared/results/run_result.h"

namespace grainlift {

/// @brief Pool the results of N >= 1 replicas into one.
///
/// Means of drag, lift, torque and contacts: pooled_mean over the replicas, the plain mean
/// with the larger of the between-replica error SD / sqrt(N) and the within-replica error
/// sqrt(sum e_i^2) / N from the replicas' own block errors (for N = 1 the replica is kept
/// as it is, its own block error included); samples: the sum; blocks: N. Surface stresses,
/// contact histograms and fields: the mean over replicas at each angle, bin and cell (over
/// the replicas where the cell is finite); surface standard errors by the same pooling rule,
/// with the replicas' per-angle errors as the within part. The force series, lid and
/// far-field series, geometry and the other diagnostics are those of the first replica.
/// Diagnostics series replica_drag, replica_lift, replica_torque hold each replica's means.
/// @throws std::invalid_argument for no replicas or replicas of different grids.
RunResult pool_replicas(const std::vector<RunResult>& replicas);

}  // namespace grainlift
