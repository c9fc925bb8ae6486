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

// Manufactured solution for the nonlinear mu(I) operator (Chauchat-Medale, d = 0.02 m,
// delta = 3 1/s, so I <= 0.2 and eta varies by a factor ~5 with |D| and p): Newton converges at
// every level and the Taylor-Hood rates hold as for Stokes: L2 velocity rate 3 +- 0.3, L2
// pressure rate 2 +- 0.3 between h = 1/16 and 1/32. (With d = 0.1, I up to ~1.4, the coarse
// levels are pre-asymptotic: rates 1.9 to 4.6 before settling to 3.)
TEST(MuIFlow, ManufacturedSolutionRates) {
  RheologyParams prm = smooth_params(Regularisation::chauchat_medale);
  prm.grain_diameter = 0.02;
  prm.delta = 3.0;
  std::vector<ManufacturedResult> runs;
  for (int level = 3; level <= 5; ++level) runs.push_back(manufactured_mu_i(level, prm));
  for (const auto& r : runs) {
    EXPECT_TRUE(r.converged);
    std::printf("mu(I) MMS h=%.4f  |u|L2 %.3e  |u|H1 %.3e  |p|L2 %.3e  iterations %d\n", r.h,
                r.velocity_l2, r.velocity_h1, r.pressure_l2, r.nonlinear_iterations);
  }
  const auto& a = runs[runs.size() - 2];
  const auto& b = runs.back();
  const double ru = std::log(a.velocity_l2 / b.velocity_l2) / std::log(2.0);
  const double rp = std::log(a.pressure_l2 / b.pressure_l2) / std::log(2.0);
  std::printf("mu(I) MMS rates: u L2 %.3f  p L2 %.3f\n", ru, rp);
  EXPECT_NEAR(ru, 3.0, 0.3);
  EXPECT_NEAR(rp, 2.0, 0.3);
}

// Steady mu(I) layer down a slope tan(theta) = 0.5 (glass beads of Jop et al. 2006), 20 grains
// deep with a small overburden: the velocity profile must match the Bagnold profile of
// verification.h to 1% of the surface velocity everywhere, and Newton must converge.
TEST(MuIFlow, InclineBagnoldProfile) {
  InclineSpec spec;
  const InclineResult r = incline_layer(spec);
  std::printf("Incline: surface velocity %.6g (exact %.6g), max rel error %.2e, picard %d newton %d\n",
              r.surface_velocity, r.surface_velocity_exact, r.max_relative_error, r.picard_steps,
              r.newton_steps);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.max_relative_error, 0.01);
}
