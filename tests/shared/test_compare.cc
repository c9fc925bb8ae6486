// `compare`: two results that differ by a known amount give exactly that difference.
#include <gtest/gtest.h>

#include <cmath>

#include "grainlift/shared/compare.h"
#include "grainlift/shared/surface_stress.h"

using namespace grainlift;

namespace {
RunResult make(double drag, double lift, double torque, double sn_shift, double st_shift, int M) {
  RunResult r;
  r.meta.solver = "x";
  r.geometry.pressure_scale = 200;
  MeanForces m;
  m.drag = drag;
  m.lift = lift;
  m.torque = torque;
  r.means = m;
  SurfaceDistribution s;
  s.theta = surface_angle_grid(M);
  for (double t : s.theta) {
    s.sigma_n.push_back(200 * (1 + std::cos(t)) + sn_shift);
    s.sigma_t.push_back(10 * std::sin(t) + st_shift);
  }
  r.surface = s;
  return r;
}
}  // namespace

TEST(Compare, KnownDifferences) {
  // B: drag +10 %, lift -50 %, torque +25 %; sigma_n shifted by 0.05 P, sigma_t by -0.02 P
  // (P = 200 Pa): L2 and max of a uniform shift both equal the shift, to 1e-12.
  const RunResult a = make(2.0, -0.4, 0.08, 0, 0, 64);
  const RunResult b = make(2.2, -0.2, 0.1, 0.05 * 200, -0.02 * 200, 64);
  const Comparison c = compare_results(a, b);
  ASSERT_TRUE(c.drag_rel && c.lift_rel && c.torque_rel);
  EXPECT_NEAR(*c.drag_rel, 0.10, 1e-12);
  EXPECT_NEAR(*c.lift_rel, 0.50, 1e-12);  // (-0.2 - -0.4) / 0.4
  EXPECT_NEAR(*c.torque_rel, 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(c.pressure_scale, 200);
  EXPECT_NEAR(c.sigma_n_l2, 0.05, 1e-12);
  EXPECT_NEAR(c.sigma_n_max, 0.05, 1e-12);
  EXPECT_NEAR(c.sigma_t_l2, 0.02, 1e-12);
  EXPECT_NEAR(c.sigma_t_max, 0.02, 1e-12);
}

TEST(Compare, DifferentAngleGridsAreInterpolated) {
  // Same smooth distribution on 64 and 128 angles: linear interpolation error of
  // 200 cos(theta) on a 2pi/128 grid is below 200 (dtheta^2 / 8) = 6e-4 P.
  const Comparison c = compare_results(make(1, 0, 0, 0, 0, 64), make(1, 0, 0, 0, 0, 128));
  EXPECT_LT(c.sigma_n_max, 6e-4);
  EXPECT_FALSE(c.lift_rel.has_value());  // A's lift is zero: no relative difference
}
