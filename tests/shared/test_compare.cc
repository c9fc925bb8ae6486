// `compare`: two results that differ by a known amount give exactly that difference.
#include <gtest/gtest.h>

#include <cmath>

#include "grainlift/shared/results/compare.h"
#include "grainlift/shared/surface/surface_stress.h"

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

TEST(Compare, AnAntisymmetricDifferenceHasNoSymmetricPart) {
  // B - A = 0.03 P sin(theta) in sigma_n (a lift-like difference) and 0.01 P cos(2 theta) in
  // sigma_t (a lift/torque-like one, symmetric). On the grid theta_{M-1-m} = -theta_m, so the
  // mirror parts of a pure sine are zero and the whole difference is antisymmetric (and the
  // other way round for a cosine): the empty part is 0 and the full part equals the total, to
  // 1e-12 (rounding of the 2 pi - theta_m mirror). The L2 (rms) of a sin(k theta) or
  // a cos(k theta) on the grid is a / sqrt(2) to rounding; its max is a within the relative
  // 1 - cos(pi / 64) = 1.2e-3 by which theta_m misses the extremum of sin(theta).
  const double P = 200;
  RunResult a = make(2.0, -0.4, 0.08, 0, 0, 64), b = a;
  for (std::size_t m = 0; m < b.surface->theta.size(); ++m) {
    const double t = b.surface->theta[m];
    b.surface->sigma_n[m] += 0.03 * P * std::sin(t);
    b.surface->sigma_t[m] += 0.01 * P * std::cos(2 * t);
  }
  const Comparison c = compare_results(a, b);
  EXPECT_NEAR(c.sigma_n_symmetric_l2, 0, 1e-12);
  EXPECT_NEAR(c.sigma_n_symmetric_max, 0, 1e-12);
  EXPECT_NEAR(c.sigma_n_antisymmetric_l2, c.sigma_n_l2, 1e-12);
  EXPECT_NEAR(c.sigma_n_antisymmetric_max, c.sigma_n_max, 1e-12);
  EXPECT_NEAR(c.sigma_n_l2, 0.03 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(c.sigma_n_max, 0.03, 0.03 * (1 - std::cos(3.14159265358979323846 / 64)));
  EXPECT_NEAR(c.sigma_t_antisymmetric_l2, 0, 1e-12);
  EXPECT_NEAR(c.sigma_t_antisymmetric_max, 0, 1e-12);
  EXPECT_NEAR(c.sigma_t_symmetric_l2, c.sigma_t_l2, 1e-12);
  EXPECT_NEAR(c.sigma_t_symmetric_max, c.sigma_t_max, 1e-12);
  EXPECT_NEAR(c.sigma_t_l2, 0.01 / std::sqrt(2.0), 1e-12);
}

TEST(Compare, TheSplitOfAMixedDifferenceAddsUpInQuadrature) {
  // The two parts are orthogonal on the grid: L2^2 = L2_sym^2 + L2_anti^2, to 1e-12.
  // Here the uniform shift 0.05 P (symmetric) plus 0.02 P sin(theta) (antisymmetric):
  // L2_sym = 0.05, L2_anti = 0.02 / sqrt 2.
  const double P = 200;
  RunResult a = make(2.0, -0.4, 0.08, 0, 0, 64), b = make(2.0, -0.4, 0.08, 0.05 * P, 0, 64);
  for (std::size_t m = 0; m < b.surface->theta.size(); ++m)
    b.surface->sigma_n[m] += 0.02 * P * std::sin(b.surface->theta[m]);
  const Comparison c = compare_results(a, b);
  EXPECT_NEAR(c.sigma_n_symmetric_l2, 0.05, 1e-12);
  EXPECT_NEAR(c.sigma_n_symmetric_max, 0.05, 1e-12);
  EXPECT_NEAR(c.sigma_n_antisymmetric_l2, 0.02 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(c.sigma_n_l2 * c.sigma_n_l2,
              c.sigma_n_symmetric_l2 * c.sigma_n_symmetric_l2 +
                  c.sigma_n_antisymmetric_l2 * c.sigma_n_antisymmetric_l2,
              1e-12);
}

TEST(Compare, DifferencesInUnitsOfTheCombinedStandardError) {
  // A (DEM) drag 2.0 +- 0.05, lift -0.4 +- 0.1, torque without a standard error; B (a steady
  // FE solution) drag 2.2, lift -0.2, no errors: drag (2.2 - 2.0) / 0.05 = 4, lift
  // 0.2 / 0.1 = 2, torque absent. With B's drag error 0.12 the combined error is
  // sqrt(0.05^2 + 0.12^2) = 0.13 and the drag difference 0.2 / 0.13. All to 1e-12.
  RunResult a = make(2.0, -0.4, 0.08, 0, 0, 64), b = make(2.2, -0.2, 0.1, 0, 0, 64);
  a.means->drag_stderr = 0.05;
  a.means->lift_stderr = 0.1;
  Comparison c = compare_results(a, b);
  ASSERT_TRUE(c.drag_z && c.lift_z);
  EXPECT_NEAR(*c.drag_z, 4.0, 1e-12);
  EXPECT_NEAR(*c.lift_z, 2.0, 1e-12);
  EXPECT_FALSE(c.torque_z.has_value());
  b.means->drag_stderr = 0.12;
  c = compare_results(a, b);
  EXPECT_NEAR(*c.drag_z, 0.2 / 0.13, 1e-12);
  // Without an error on either side there is no error scale: absent, also in the JSON (null).
  const Comparison none =
      compare_results(make(2.0, -0.4, 0.08, 0, 0, 64), make(2.2, -0.2, 0.1, 0, 0, 64));
  EXPECT_FALSE(none.drag_z || none.lift_z || none.torque_z);
  EXPECT_EQ(none.error_kind_a, "none");
  const std::string json = comparison_json(c);
  for (const char* key : {"\"drag_z\"", "\"torque_z\":null", "\"sigma_n_symmetric_l2\"",
                          "\"sigma_t_antisymmetric_max\"", "\"drag_rel\"", "\"sigma_n_l2\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
  const std::string text = comparison_text(c);
  EXPECT_NE(text.find("(B-A)/se +1.54"), std::string::npos) << text;
  EXPECT_NE(text.find("sigma_n symmetric: L2"), std::string::npos) << text;
}

TEST(Compare, TheFemMeshErrorEstimateJoinsTheCombinedError) {
  // A (DEM) drag 2.0 +- 0.05, lift -0.4 +- 0.1; B a steady FE solution whose /diagnostics
  // carry the change from the next coarser level, drag 0.12 and lift 0 (a mesh-converged lift):
  // the drag difference 0.2 is in units of sqrt(0.05^2 + 0.12^2) = 0.13, the lift's 0.2 in
  // units of 0.1 alone; the torque (no error on A, and B's estimate 0.3) in units of 0.3. The
  // JSON says which kind of error each side has. All to 1e-12.
  RunResult a = make(2.0, -0.4, 0.08, 0, 0, 64), b = make(2.2, -0.2, 0.1, 0, 0, 64);
  a.means->drag_stderr = 0.05;
  a.means->lift_stderr = 0.1;
  a.means->torque = 1.0;
  b.means->torque = 1.6;
  b.diagnostics.values = {{"drag_mesh_error", 0.12}, {"lift_mesh_error", 0.0},
                          {"torque_mesh_error", 0.3}};
  const Comparison c = compare_results(a, b);
  ASSERT_TRUE(c.drag_z && c.lift_z && c.torque_z);
  EXPECT_NEAR(*c.drag_z, 0.2 / 0.13, 1e-12);
  EXPECT_NEAR(*c.lift_z, 2.0, 1e-12);
  EXPECT_NEAR(*c.torque_z, 2.0, 1e-12);
  EXPECT_EQ(c.error_kind_a, "standard error");
  EXPECT_EQ(c.error_kind_b, "mesh-error estimate");
  const std::string json = comparison_json(c);
  for (const char* key : {"\"drag_err_b\":0.12", "\"error_kind_b\":\"mesh-error estimate\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
}
