// solve_flow(): adaptive cycles that stop at continuum.target_error (after the nested levels).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cylinder_case.h"
#include "grainlift/continuum/solver.h"

using namespace grainlift::continuum;

// Adaptive cycles on top of the nested levels carry the nested levels' error estimate on:
// after each cycle e = d max(1, r / (1 - r)) / |F| from the changes d of the force over the
// last three meshes (levels and cycles in order) and their ratio r. On the spinning cylinder
// of the nested test (Omega = 2, 1 m box, refinement 1 then Kelly's 30% per cycle):
// - every mesh is reported (levels 0 and 1, then cycles 1-3 on refinement 1), each converged;
// - the estimate covers the error against the finest mesh, not only the next change: at
//   cycles 1 and 2, |F_3 - F_k| / |F_k| <= e_k (cycle 3 has 3.4x cycle 1's cells);
// - with the target just above e_1 the run stops at cycle 1, with the reference's cycle-1
//   forces exactly (the same meshes and solves) and e_1 reported.
TEST(Cylinder, AdaptiveCyclesStopAtTheTargetAndTheirEstimateCoversTheFinestMesh) {
  ContinuumConfig c = grainlift::continuum::test::coarse_case();
  c.intruder_omega = 4.0;
  c.adaptive_cycles = 3;
  const ContinuumOutput ref = solve_flow(c);
  ASSERT_TRUE(ref.converged) << ref.message;
  ASSERT_EQ(ref.levels.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(ref.levels[k].converged);
    EXPECT_EQ(ref.levels[k].adaptive_cycle, std::max(0, k - 1));
    EXPECT_EQ(ref.levels[k].refinement, std::min(k, 1));
  }
  const auto& L = ref.levels;
  auto d = [&](int a, int b) { return std::hypot(L[a].fx - L[b].fx, L[a].fy - L[b].fy); };
  auto estimate = [&](int k) {  // the estimate after mesh k (k >= 2)
    const double r = d(k, k - 1) / d(k - 1, k - 2);
    return r < 1 ? d(k, k - 1) * std::max(1.0, r / (1 - r)) / std::hypot(L[k].fx, L[k].fy)
                 : 1.0;
  };
  for (int k = 2; k <= 3; ++k) {
    const double F = std::hypot(L[k].fx, L[k].fy), err = d(4, k) / F;
    std::printf("cycle %d: %d cells, estimate %.4g, error against cycle 3 (%d cells) %.4g\n",
                k - 1, L[k].cells, estimate(k), L[4].cells, err);
    EXPECT_LE(err, estimate(k));
  }
  EXPECT_GT(L[4].cells, 3 * L[2].cells);

  c.target_error = 1.001 * estimate(2);
  const ContinuumOutput out = solve_flow(c);
  ASSERT_TRUE(out.converged) << out.message;
  EXPECT_TRUE(out.target_met);
  ASSERT_EQ(out.levels.size(), 3u);
  EXPECT_EQ(out.levels.back().adaptive_cycle, 1);
  EXPECT_NEAR(out.estimated_error, estimate(2), 1e-12);
  EXPECT_EQ(out.fx, L[2].fx);
  EXPECT_EQ(out.fy, L[2].fy);
}
