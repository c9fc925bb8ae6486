// The nonlocal granular fluidity model on the cylinder problem (continuum.model =
// "nonlocal_fluidity", fluidity/nonlocal_coupling.cc): its local limit, its settling, and the
// direction of its effect.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/solver.h"

using namespace grainlift::continuum;

namespace {

// A spinning cylinder (Omega = omega R / V = 2) in a symmetric box, P0 = 1000 Pa, Jop's mu(I)
// with the Chauchat-Medale regularisation (whose viscosity cap mu_s p / (2 delta) is the
// nonlocal model's at its fluidity floor g_min = 2 delta / mu_s), refinement 1.
ContinuumConfig spinning_case() {
  ContinuumConfig c;
  c.intruder_diameter = 0.1;
  c.half_width = 0.5;
  c.half_height = 0.5;
  c.intruder_velocity = {0.1, 0};
  c.intruder_omega = 4.0;
  c.ambient_pressure = 1000;
  c.refinement = 1;
  c.inertia = InertiaMode::off;
  c.rheology.regularisation = Regularisation::chauchat_medale;
  c.rheology.grain_diameter = 0.01;
  return c;
}

ContinuumOutput nonlocal(double amplitude, double tolerance = 2e-3) {
  ContinuumConfig c = spinning_case();
  c.model = ContinuumModel::nonlocal_fluidity;
  c.nonlocal.amplitude = amplitude;
  c.nonlocal.tolerance = tolerance;
  const ContinuumOutput out = solve_flow(c, [](const std::string& s) {
    if (s.find("nonlocal") != std::string::npos) std::printf("%s\n", s.c_str());
  });
  if (!out.converged) std::printf("not converged: %s\n", out.message.c_str());
  std::printf("A = %g: F = (%.6g, %.6g) N/m, T = %.6g N, %d iterations, |dg|/|g| = %.3g\n",
              amplitude, out.fx, out.fy, out.torque, out.nonlocal_iterations,
              out.nonlocal_change);
  return out;
}

}  // namespace

// With xi -> 0 the fluidity equation gives g = g_loc(mu, p) and eta = p / g_loc = mu(I) p /
// gamma_dot: Jop's local law. At A = 0.01 (xi = 0.1 d at |mu - mu_s| = 0.01, far below the
// cell size D / 8) the Q2 fluidity smears g_loc's jump at mu_s over a cell, so the limit holds
// only roughly on this mesh: the drag and the torque within 3% of the local solver's
// (measured 1.5% and 0.4%), the lift not (12% of itself: the creeping side sets it).
// Cooperativity spreads fluidity from the sheared layer into the creeping bed (Kamrin & Koval
// 2012; the secondary rheology of Reddy et al. 2011): the bed round the intruder softens and
// the drag falls, the more the longer xi. At A = 0.5 and 1 (xi = 5 d and 10 d at |mu - mu_s|
// = 0.01, capped at D) the splitting must settle (force and torque still to 2e-3 in two
// iterations running) with the drag at least 3% below the A = 0.01 value (measured 9%), and
// lower at A = 1 than at 0.5.
TEST(NonlocalFluidity, LocalLimitAndCooperativitySoftensTheBed) {
  const ContinuumOutput local = solve_flow(spinning_case());
  ASSERT_TRUE(local.converged) << local.message;
  std::printf("local: F = (%.6g, %.6g) N/m, T = %.6g N\n", local.fx, local.fy, local.torque);
  const ContinuumOutput near = nonlocal(0.01, 5e-3);
  EXPECT_NEAR(near.fx, local.fx, 0.03 * std::abs(local.fx));
  EXPECT_NEAR(near.torque, local.torque, 0.03 * std::abs(local.torque));
  const ContinuumOutput a05 = nonlocal(0.5), a1 = nonlocal(1.0);
  for (const ContinuumOutput* out : {&a05, &a1}) {
    ASSERT_TRUE(out->converged) << out->message;
    EXPECT_TRUE(out->nonlocal_settled);
  }
  EXPECT_LT(-a05.fx, 0.97 * -near.fx);
  EXPECT_LT(-a1.fx, -a05.fx);
}

// The splitting solves gravity in full and runs on one rank: the linearised treatment is
// refused with a ConfigError naming the key to change.
TEST(NonlocalFluidity, LinearisedGravityIsRefused) {
  ContinuumConfig c = spinning_case();
  c.model = ContinuumModel::nonlocal_fluidity;
  c.gravity = {0, -0.1};  // small: the lithostatic pressure stays positive in the box
  c.bulk_density = 1500;
  c.linearised_gravity = true;
  try {
    solve_flow(c);
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    std::printf("%s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("gravity_treatment"), std::string::npos) << e.what();
  }
}
