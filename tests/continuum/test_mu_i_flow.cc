// mu(I) operator: Newton Jacobian, manufactured solution, Bagnold layer down an incline.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grainlift/continuum/verification.h"

using namespace grainlift::continuum;
using namespace grainlift::continuum::verification;

namespace {
// Smooth mu(I) parameters for the unit-square problems: I ~ 0.1-1 with |D| ~ 1-10 1/s, p ~ 1-3 Pa.
RheologyParams smooth_params(Regularisation reg) {
  RheologyParams p;
  p.grain_diameter = 0.1;
  p.solid_density = 1.0;
  p.delta = 1.0;
  p.eta_max = 1e6;
  p.eta_min = 1e-8;
  p.regularisation = reg;
  p.barker_gray_IN = 0.05;
  return p;
}

/// The manufactured mu(I) solution at h = 1/8, 1/16, 1/32 (Chauchat-Medale, d = 0.02 m, delta
/// = 3 1/s; dilatant with delta(I) = @p dilatancy_a I when > 0): Newton converges on every
/// level, and the L2 rates between the two finest are 3 (u) and 2 (p) within 0.3.
void expect_manufactured_rates(const char* label, double dilatancy_a) {
  RheologyParams prm = smooth_params(Regularisation::chauchat_medale);
  prm.grain_diameter = 0.02;
  prm.delta = 3.0;
  std::vector<ManufacturedResult> runs;
  for (int level = 3; level <= 5; ++level)
    runs.push_back(manufactured_mu_i(level, prm, dilatancy_a));
  for (const auto& r : runs) {
    EXPECT_TRUE(r.converged);
    std::printf("%s MMS h=%.4f  |u|L2 %.3e  |u|H1 %.3e  |p|L2 %.3e  iterations %d\n", label,
                r.h, r.velocity_l2, r.velocity_h1, r.pressure_l2, r.nonlinear_iterations);
  }
  const auto& a = runs[runs.size() - 2];
  const auto& b = runs.back();
  const double ru = std::log(a.velocity_l2 / b.velocity_l2) / std::log(2.0);
  const double rp = std::log(a.pressure_l2 / b.pressure_l2) / std::log(2.0);
  std::printf("%s MMS rates: u L2 %.3f  p L2 %.3f\n", label, ru, rp);
  EXPECT_NEAR(ru, 3.0, 0.3);
  EXPECT_NEAR(rp, 2.0, 0.3);
}
}  // namespace

// The assembled Newton matrix (with d eta/d|D|^2, d eta/dp, inertia and the Coulomb wall) is the
// derivative of the assembled residual: |J d - (R(x+hd) - R(x-hd))/2h|_inf < 1e-6 |FD|_inf.
TEST(MuIFlow, JacobianMatchesFiniteDifferences) {
  for (const auto reg : {Regularisation::chauchat_medale, Regularisation::barker_gray})
    for (const bool inertia : {false, true})
      for (const bool wall : {false, true}) {
        const JacobianCheck c = check_jacobian(smooth_params(reg), inertia, wall);
        std::printf("Jacobian FD check reg=%d inertia=%d wall=%d: relative error %.2e\n",
                    static_cast<int>(reg), inertia, wall, c.relative_error());
        EXPECT_GT(c.max_abs_reference, 0);
        EXPECT_LT(c.relative_error(), 1e-6) << "reg " << static_cast<int>(reg) << " inertia "
                                            << inertia << " wall " << wall;
      }
}

// The same check for a dilatant medium (delta(I) = 0.4 I, continuum.dilatancy's law): the
// matrix differentiates delta through I(|D|^2, p) in the weight, the continuity's volume form
// and its boundary flux (Dirichlet, traction and Coulomb sides), to the same 1e-6.
TEST(MuIFlow, DilatantJacobianMatchesFiniteDifferences) {
  for (const bool wall : {false, true}) {
    const JacobianCheck c =
        check_jacobian(smooth_params(Regularisation::chauchat_medale), false, wall, 0.4);
    std::printf("dilatant Jacobian FD check wall=%d: relative error %.2e\n", wall,
                c.relative_error());
    EXPECT_GT(c.max_abs_reference, 0);
    EXPECT_LT(c.relative_error(), 1e-6) << "wall " << wall;
  }
}

// Manufactured solution for the nonlinear mu(I) operator (Chauchat-Medale, d = 0.02 m,
// delta = 3 1/s, so I <= 0.2 and eta varies by a factor ~5 with |D| and p): Newton converges at
// every level and the Taylor-Hood rates hold as for Stokes: L2 velocity rate 3 +- 0.3, L2
// pressure rate 2 +- 0.3 between h = 1/16 and 1/32. (With d = 0.1, I up to ~1.4, the coarse
// levels are pre-asymptotic: rates 1.9 to 4.6 before settling to 3.)
TEST(MuIFlow, ManufacturedSolutionRates) { expect_manufactured_rates("mu(I)", 0); }

// The dilatant medium (continuum.dilatancy's law, delta(I) = 0.4 I here: the packing falls by
// up to 8% where I ~ 0.2) on the same manufactured fields: a non-solenoidal continuity
// div((1 - delta) u) = -u.grad delta of the exact fields (both the volume form and its
// boundary flux on the Dirichlet and traction sides) and the body force divided by 1 - delta.
// delta is the discrete state's, so its error enters both equations: the Taylor-Hood rates
// (u L2 3, p L2 2) hold only if the dilatant terms are consistent, within 0.3 as above.
TEST(MuIFlow, DilatantManufacturedSolutionRates) { expect_manufactured_rates("dilatant", 0.4); }

// Steady mu(I) layer down a slope tan(theta) = 0.5 (glass beads of Jop et al. 2006), 20 grains
// deep with a small overburden: the velocity profile must match the Bagnold profile of
// verification.h to 1% of the surface velocity everywhere, and Newton must converge.
TEST(MuIFlow, InclineBagnoldProfile) {
  InclineSpec spec;
  const InclineResult r = incline_layer(spec);
  std::printf(
      "Incline: surface velocity %.6g (exact %.6g), max rel error %.2e, picard %d newton %d\n",
      r.surface_velocity, r.surface_velocity_exact, r.max_relative_error, r.picard_steps,
      r.newton_steps);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.max_relative_error, 0.01);
}

// Newton's tangent floor (NonlinearSettings::tangent_floor, the refined meshes' last approach)
// changes the matrix only. On the same incline (tan theta = 0.5: mu = 0.5 everywhere, where the
// tangent of Jop's law is 13% of the secant) a floor of 20% acts on every quadrature point:
// Newton loses its quadratic convergence (more steps than with the exact Jacobian) but still
// converges to the tight tolerance, to the same surface velocity (1e-6 relative: the residual,
// and so the discrete solution, is the same) and the same 1% match of the Bagnold profile.
TEST(MuIFlow, TangentFloorChangesTheMatrixNotTheSolution) {
  InclineSpec exact, floored;
  floored.tangent_floor = 0.2;
  const InclineResult a = incline_layer(exact), b = incline_layer(floored);
  std::printf("Incline: exact Jacobian %d Newton steps, tangent floor 0.2: %d; surface velocity "
              "%.9g and %.9g\n", a.newton_steps, b.newton_steps, a.surface_velocity,
              b.surface_velocity);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged);
  EXPECT_GT(b.newton_steps, a.newton_steps);
  EXPECT_NEAR(b.surface_velocity, a.surface_velocity, 1e-6 * a.surface_velocity);
  EXPECT_LT(b.max_relative_error, 0.01);
}

// ---- The lid of the periodic box (the cylinder problem's far field with a wall on top): a
// rigid lid whose load per length is P_lid times its length, imposed as the mean pressure on it
// (BoundarySpec::mean_pressure), over a wall at rest, periodic in x, no intruder.

// At rest under gravity the medium is hydrostatic: p = P_lid + rho g (H - y) everywhere (a
// linear pressure, exact in the Q1 space: to the solver tolerance), starting from a uniform P_lid.
TEST(LidBox, LidAtRestGivesTheHydrostaticPressure) {
  LidBoxSpec s;
  s.lid_pressure = 100;  // Pa: the weight of the layer is 1500 * 9.81 * 0.02 = 294 Pa, 2.9 P_lid
  s.gravity = 9.81;
  s.rheology.grain_diameter = 1.5e-3;
  s.rheology.solid_density = 2500;
  const LidBoxResult r = lid_box(s);
  ASSERT_TRUE(r.converged);
  EXPECT_LT(r.max_pressure_error, 1e-8);
  EXPECT_NEAR(r.lid_mean_pressure, 100, 1e-6);  // the lid's load per length / its length
}

// A sheared dilatant layer (delta(I) = 0.3 I) under gravity carries the weight of its dilated
// grains: with the lid sliding, I falls with depth as p grows, and p = P_lid + rho g int_y^H
// (1 - delta(I(y'))) dy' (delta from the solution's own I on the column); the incompressible
// hydrostatic p would be off by the weight deficit, asserted 20 times the tolerance (1e-4
// P_lid: Q1 pressure on 16 cells through a profile that is no longer linear).
TEST(LidBox, ShearedDilatantLayerCarriesTheWeightOfItsDilatedGrains) {
  LidBoxSpec s;
  s.lid_pressure = 100;
  s.gravity = 9.81;
  s.bulk_density = 100;  // the layer's weight 19.6 Pa, 0.2 P_lid: mu > mu_s through the depth
  s.cells_y = 16;
  s.rheology.grain_diameter = 1.5e-3;
  s.rheology.solid_density = 2500;
  s.lid_speed = 0.3 * s.height * std::sqrt(100.0 / 2500.0) / 1.5e-3;  // I ~ 0.3 at the top
  s.dilatancy_a = 0.3;
  const LidBoxResult r = lid_box(s);
  ASSERT_TRUE(r.converged);
  std::printf("dilatant lid box: pressure error %.2e P_lid, weight deficit %.4f P_lid\n",
              r.max_pressure_error, r.weight_deficit);
  EXPECT_LT(r.max_pressure_error, 1e-4);
  EXPECT_GT(r.weight_deficit, 2e-3);
}

// A lid sliding at U over the wall shears the layer uniformly: u = U y / H, p = P_lid and
// tau = mu(I) P_lid with I = (U/H) d / sqrt(P_lid / rho_s) (Jop et al. 2006's law; GDR MiDi's
// plane shear). A linear profile and a constant pressure are exact in Q2-Q1: to 1e-6.
TEST(LidBox, SlidingLidGivesTheMuISimpleShear) {
  LidBoxSpec s;
  s.lid_pressure = 100;
  s.rheology.grain_diameter = 1.5e-3;
  s.rheology.solid_density = 2500;
  // I = 0.1: U = I H sqrt(P / rho_s) / d
  s.lid_speed = 0.1 * s.height * std::sqrt(100.0 / 2500.0) / 1.5e-3;
  const LidBoxResult r = lid_box(s);
  ASSERT_TRUE(r.converged);
  std::printf("lid box shear: tau %.9g Pa, mu(I) P %.9g Pa, velocity error %.2e, p error %.2e\n",
              r.lid_shear_stress, r.shear_stress_exact, r.max_velocity_error,
              r.max_pressure_error);
  EXPECT_LT(r.max_velocity_error, 1e-6);
  EXPECT_LT(r.max_pressure_error, 1e-6);
  EXPECT_NEAR(r.lid_shear_stress / r.shear_stress_exact, 1.0, 1e-6);
  EXPECT_NEAR(r.lid_mean_pressure, 100, 1e-4);
}
