// The nonlocal granular fluidity model on the cylinder problem (continuum.model =
// "nonlocal_fluidity", fluidity/nonlocal_coupling.cc): its local limit, its settling, and the
// direction of its effect.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cylinder_case.h"
#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/solver.h"
#include "grainlift/continuum/verification.h"

using namespace grainlift::continuum;

namespace {

// A spinning cylinder (Omega = omega R / V = 2) in a symmetric box, P0 = 1000 Pa, Jop's mu(I)
// with the Chauchat-Medale regularisation (whose viscosity cap mu_s p / (2 delta) is the
// nonlocal model's at its fluidity floor g_min = 2 delta / mu_s), refinement 1.
ContinuumConfig spinning_case() {
  ContinuumConfig c = grainlift::continuum::test::coarse_case();
  c.surface_theta.clear();
  c.intruder_omega = 4.0;
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
// (measured 0.9% and 0.1%), the lift not (11% of itself: the creeping side sets it).
// Cooperativity spreads fluidity from the sheared layer into the creeping bed (Kamrin & Koval
// 2012; the secondary rheology of Reddy et al. 2011): the bed round the intruder softens and
// the drag falls, the more the longer xi. At A = 0.5 and 1 (xi = 5 d and 10 d at |mu - mu_s|
// = 0.01, capped at D) the splitting must settle (force and torque still to 2e-3 in two
// iterations running) with the drag at least 3% below the A = 0.01 value (measured 8%), and
// lower at A = 1 than at 0.5. The surface integral of sigma.n, whose stress reads g at the
// faces' points, is a second estimate of the force: where xi spans cells (A = 0.5, 1) the
// stress at the surface is smooth and it is within 5% of the consistent reaction (measured
// 0.8-1.1%; 150x off while the faces' points read the floor g_min). On this coarse mesh the
// local law's and A = 0.01's are 14% and 25% off (sigma(grad u_h).n converges slowly): not
// asserted.
TEST(NonlocalFluidity, LocalLimitAndCooperativitySoftensTheBed) {
  const ContinuumOutput local = solve_flow(spinning_case());
  ASSERT_TRUE(local.converged) << local.message;
  std::printf("local: F = (%.6g, %.6g) N/m, T = %.6g N, surface integral (%.6g, %.6g)\n",
              local.fx, local.fy, local.torque, local.force_fx_surface, local.force_fy_surface);
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
  for (const ContinuumOutput* out : {&a05, &a1}) {
    std::printf("reaction (%.6g, %.6g), surface integral (%.6g, %.6g) N/m\n", out->fx, out->fy,
                out->force_fx_surface, out->force_fy_surface);
    const double F = std::hypot(out->fx, out->fy);
    EXPECT_LT(std::hypot(out->force_fx_surface - out->fx, out->force_fy_surface - out->fy),
              0.05 * F);
  }
}

// Nested levels carry g, the flow and the flow step's table from each level to the next
// (solve_nonlocal_fluidity()); the finest level's splitting must reach the fixed point that
// the splitting from the local law's state on that mesh alone reaches: the same discrete
// problem. Both stop where the force and torque move by less than 2e-3 of themselves in two
// iterations, so they may differ by a few of those: within 1% of |F| in F and of |T| in T
// (measured at refinement 1: 0.28% and 0.7%; at refinement 2 with a 2e-4 stop, 0.15% and
// 0.4%). The iteration counts on the last level (at refinement 2 with a 2e-4 stop: 44 alone
// and 15 nested, 20 and 40 with the mixing in g instead of log g) say more about where the
// splitting hovers at that stop than about the start: not asserted.
TEST(NonlocalFluidity, NestedLevelsReachTheSingleLevelFixedPoint) {
  ContinuumOutput out[2];
  for (const bool nested : {false, true}) {
    ContinuumConfig c = spinning_case();
    c.refinement = 1;
    c.nested = nested;
    c.model = ContinuumModel::nonlocal_fluidity;
    c.nonlocal.amplitude = 0.5;
    out[nested] = solve_flow(c, nullptr);
    ASSERT_TRUE(out[nested].converged) << out[nested].message;
    EXPECT_TRUE(out[nested].nonlocal_settled);
    std::printf("nested %d: F = (%.8g, %.8g) N/m, T = %.8g N, %d iterations on the last level\n",
                nested, out[nested].fx, out[nested].fy, out[nested].torque,
                out[nested].nonlocal_iterations);
  }
  const double F = std::hypot(out[0].fx, out[0].fy);
  EXPECT_LT(std::hypot(out[1].fx - out[0].fx, out[1].fy - out[0].fy), 0.01 * F);
  EXPECT_NEAR(out[1].torque, out[0].torque, 0.01 * std::abs(out[0].torque));
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

// The splitting's flow step solves eta = p+ / g by Newton with g held fixed (FluidityViscosity:
// d eta / dp = 1 / g, d eta / d|D|^2 = 0). Its assembled Jacobian must be the derivative of its
// assembled residual, as the local law's is (MuIFlow.JacobianMatchesFiniteDifferences): with a
// smooth fluidity g = 1 + x + y / 2 on the unit square, p = 2 + cos(pi x) cos(pi y) > 0,
// |J d - (R(x + h d) - R(x - h d)) / 2h|_inf < 1e-6 |FD|_inf, with a Dirichlet side and with a
// regularised Coulomb wall. (Quadratic convergence of the step follows; the coupled fixed point
// is the splitting's, not a Newton's.)
TEST(NonlocalFluidity, FlowStepJacobianMatchesFiniteDifferences) {
  RheologyParams p;
  p.grain_diameter = 0.1;
  p.solid_density = 1.0;
  p.delta = 0.1;  // g_min = 2 delta / mu_s = 0.53 1/s, below the field's 1 to 2.5
  p.eta_max = 1e6;
  p.eta_min = 1e-8;
  for (const bool implicit : {false, true})
    for (const bool wall : {false, true}) {
      const verification::JacobianCheck c =
          verification::check_jacobian_fluidity(p, wall, implicit);
      std::printf("fluidity flow step Jacobian, wall=%d, local part implicit=%d: relative "
                  "error %.2e\n", wall, implicit, c.relative_error());
      EXPECT_GT(c.max_abs_reference, 0);
      EXPECT_LT(c.relative_error(), 1e-6) << "wall " << wall << " implicit " << implicit;
    }
}

// The coupled system with known fields (verification::manufactured_coupled_fluidity): the flow
// with eta = p+ / g_h and the fluidity with xi and g_loc of the discrete flow, alternated until g
// stops changing, must converge at the elements' optimal rates, Q2 velocity and fluidity h^3 and
// Q1 pressure h^2 in L2, from refinement 2 to 4 (rates at least 2.7, 2.7 and 1.7; mu in
// (0.26, 0.73), between mu_s 0.1 and mu(I = 1) 0.79 of these grains, so g_loc is smooth there).
TEST(NonlocalFluidity, CoupledManufacturedSolutionAtOptimalRates) {
  RheologyParams p;
  p.mu_s = 0.1;
  p.mu_2 = 1.0;
  p.I0 = 0.3;
  p.grain_diameter = 0.1;
  p.solid_density = 1.0;
  p.delta = 0.01;  // g_min = 0.2, below the field's 1.1
  p.eta_max = 1e6;
  p.eta_min = 1e-8;
  std::vector<verification::CoupledManufacturedResult> r;
  for (int level = 2; level <= 4; ++level) {
    r.push_back(verification::manufactured_coupled_fluidity(level, p));
    const auto& e = r.back();
    std::printf("h = %.4g: |u - u_h| %.3e, |p - p_h| %.3e, |g - g_h| %.3e (H1 %.3e), %d "
                "alternations%s\n", e.h, e.velocity_l2, e.pressure_l2, e.fluidity_l2,
                e.fluidity_h1, e.iterations, e.converged ? "" : " (not converged)");
    EXPECT_TRUE(e.converged);
  }
  for (std::size_t k = 1; k < r.size(); ++k) {
    const double ru = std::log2(r[k - 1].velocity_l2 / r[k].velocity_l2);
    const double rp = std::log2(r[k - 1].pressure_l2 / r[k].pressure_l2);
    const double rg = std::log2(r[k - 1].fluidity_l2 / r[k].fluidity_l2);
    std::printf("rates: u %.2f, p %.2f, g %.2f\n", ru, rp, rg);
    EXPECT_GT(ru, 2.7);
    EXPECT_GT(rp, 1.7);
    EXPECT_GT(rg, 2.7);
  }
}

namespace {

/// The sheared layer round a cylinder spinning in place (V = 0.005 m/s, omega R = 0.4 m/s:
/// annular shear), its width: the distance from the surface, along the ray above the centre,
/// at which the speed relative to the far field first falls below 1% of omega R.
double annular_width(double grain_diameter, ContinuumModel model) {
  ContinuumConfig c = spinning_case();
  c.intruder_velocity = {0.005, 0};
  c.intruder_omega = 8.0;
  c.rheology.grain_diameter = grain_diameter;
  c.model = model;
  c.nonlocal.amplitude = 0.5;
  c.nonlocal.tolerance = 5e-3;
  c.fields.enabled = true;
  c.fields.x0 = 0;
  c.fields.y0 = 0.05;
  c.fields.spacing = 0.0025;
  c.fields.nx = 1;
  c.fields.ny = 180;  // to y = 0.4975, inside the box's half height 0.5
  const ContinuumOutput out = solve_flow(c);
  EXPECT_TRUE(out.converged) << out.message;
  const double omega_r = 8.0 * 0.05;
  for (int j = 0; j < c.fields.ny; ++j) {
    const double y = c.fields.y0 + j * c.fields.spacing;
    const double s = std::hypot(out.vx[std::size_t(j)] + 0.005, out.vy[std::size_t(j)]);
    if (std::isfinite(s) && s < 0.01 * omega_r) return y - 0.05;
  }
  return c.fields.ny * c.fields.spacing;
}

}  // namespace

// Annular shear round a cylinder spinning in place: the local law confines the flow to where
// mu > mu_s, at a radius set by the stress field, nearly independent of the grain size; the
// nonlocal model spreads it by the cooperativity length xi = A d / sqrt|mu - mu_s|, which grows
// with d (Kamrin & Koval 2012: the width of a shear band in a split-bottom or annular cell
// grows with d). At A = 0.5, doubling d (0.01 to 0.02 m) must widen the nonlocal layer's excess
// over the local one by more than 1.5x (xi proportional to d gives 2; measured 25 to 52.5 mm,
// 2.1x, at refinement 1 sampled every 2.5 mm), and the nonlocal layer must be wider than the
// local one at both sizes (measured 47.5 and 77.5 mm against 22.5 and 25 mm).
TEST(NonlocalFluidity, AnnularShearLayerWidensWithTheGrainSize) {
  const double local1 = annular_width(0.01, ContinuumModel::local);
  const double local2 = annular_width(0.02, ContinuumModel::local);
  const double ngf1 = annular_width(0.01, ContinuumModel::nonlocal_fluidity);
  const double ngf2 = annular_width(0.02, ContinuumModel::nonlocal_fluidity);
  std::printf("annular width (m): local %.4f, %.4f; nonlocal %.4f, %.4f (d = 0.01, 0.02 m)\n",
              local1, local2, ngf1, ngf2);
  EXPECT_GT(ngf1, local1);
  EXPECT_GT(ngf2, local2);
  EXPECT_GT(ngf2 - local2, 1.5 * (ngf1 - local1));
}
