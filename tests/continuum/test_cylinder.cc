// solve_flow(): the cylinder problem itself.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/solver.h"

using namespace grainlift::continuum;

namespace {
ContinuumConfig coarse_case() {
  ContinuumConfig c;
  c.intruder_diameter = 0.1;
  c.half_width = 0.5;
  c.half_height = 0.5;
  c.intruder_velocity = {0.1, 0};
  c.ambient_pressure = 1000;
  c.refinement = 1;
  c.inertia = InertiaMode::off;
  c.surface_theta = {0.0, M_PI / 4, M_PI / 2, -M_PI / 2, M_PI};
  return c;
}
}  // namespace

// No gravity, no spin: the problem is symmetric about the axis of motion, so the lift must
// vanish to solver tolerance (|L| < 1e-6 D) while the drag is positive; sigma_n is symmetric
// (sigma_n(pi/2) = sigma_n(-pi/2) to 1e-6 relative) and compressive at the front.
TEST(Cylinder, NoGravityNoSpinHasNoLift) {
  ContinuumConfig c = coarse_case();
  const auto t0 = std::chrono::steady_clock::now();
  const ContinuumOutput out = solve_flow(c, [](const std::string& s) { std::printf("%s\n", s.c_str()); });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("cylinder: %d cells %d dofs, picard %d newton %d, %.2f s, F = (%.6g, %.6g), T = %.3g\n",
              out.cells, out.dofs, out.picard_steps, out.newton_steps, secs, out.fx, out.fy, out.torque);
  ASSERT_TRUE(out.converged) << out.message;
  const double drag = -out.fx, lift = out.fy;  // V along +x
  EXPECT_GT(drag, 0);
  EXPECT_LT(std::abs(lift), 1e-6 * drag);
  EXPECT_LT(std::abs(out.torque), 1e-6 * drag * 0.05);
  ASSERT_EQ(out.sigma_n.size(), 5u);
  EXPECT_GT(out.sigma_n[0], 0);
  EXPECT_NEAR(out.sigma_n[2], out.sigma_n[3], 1e-6 * std::abs(out.sigma_n[0]));
}

// Out-of-range configuration values are reported as ConfigError, never as a crash.
TEST(Cylinder, BadConfigurationThrowsConfigError) {
  ContinuumConfig c = coarse_case();
  c.intruder_diameter = -1;
  EXPECT_THROW(solve_flow(c), ConfigError);
  c = coarse_case();
  c.gravity = {0, -9.81};
  c.bulk_density = 1500;
  c.ambient_pressure = 100;  // rho g H = 7357 Pa > P0: negative pressure at the top
  EXPECT_THROW(solve_flow(c), ConfigError);
}
