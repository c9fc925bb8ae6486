// The fluidity equation of the nonlocal granular fluidity model (Kamrin & Koval, PRL 108,
// 178301, 2012), g - xi^2 Laplacian(g) = g_loc, solved alone (the building block of
// continuum.model = "nonlocal_fluidity"): its exact boundary layer in planar shear, the
// uniform state under zero flux, a manufactured solution with variable xi, and the capped
// cooperativity length (the shared law, fluidity_law.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "grainlift/shared/rheology/fluidity_law.h"
#include "grainlift/continuum/fluidity/fluidity_verification.h"

using namespace grainlift::continuum::fluidity;
using namespace grainlift::continuum::fluidity::verification;

namespace {
/// Observed orders log(e_k / e_{k+1}) / log(h_k / h_{k+1}) of successive runs.
std::vector<double> observed_orders(const std::vector<FluidityErrors>& runs,
                                    double FluidityErrors::*norm) {
  std::vector<double> orders;
  for (std::size_t k = 0; k + 1 < runs.size(); ++k)
    orders.push_back(std::log(runs[k].*norm / runs[k + 1].*norm) /
                     std::log(runs[k].h / runs[k + 1].h));
  return orders;
}

void print_runs(const char* name, int degree, const std::vector<FluidityErrors>& runs) {
  const auto l2 = observed_orders(runs, &FluidityErrors::l2);
  const auto h1 = observed_orders(runs, &FluidityErrors::h1);
  for (std::size_t k = 0; k < runs.size(); ++k)
    std::printf("%s Q%d h=%.5f cells %5d dofs %6d  L2 %.3e (order %.3f)  H1 %.3e (order %.3f)\n",
                name, degree, runs[k].h, runs[k].cells, runs[k].dofs, runs[k].l2,
                k ? l2[k - 1] : 0.0, runs[k].h1, k ? h1[k - 1] : 0.0);
}
}  // namespace

// Planar shear layer 0 < y < H = 1 m, uniform g_loc = 2 1/s and xi = 0.1 m, g = g_w = 0.5 1/s
// at both walls: the fluidity relaxes from g_w to g_loc over a boundary layer of thickness xi,
// g(y) = g_loc + (g_w - g_loc) cosh((y - H/2)/xi) / cosh(H/(2 xi)). Four meshes, h = H/16 to
// H/128 (h/xi = 0.625 to 0.078); every observed order of the L2 error must be the optimal one,
// degree + 1, within 0.15, and that of the H1 seminorm, degree, within 0.15.
TEST(Fluidity, PlanarShearBoundaryLayerAtOptimalRates) {
  const PlanarShear layer;
  for (int degree : {1, 2}) {
    std::vector<FluidityErrors> runs;
    for (int refinement = 2; refinement <= 5; ++refinement)
      runs.push_back(planar_shear_fluidity(layer, refinement, degree));
    print_runs("planar shear", degree, runs);
    for (double order : observed_orders(runs, &FluidityErrors::l2))
      EXPECT_NEAR(order, degree + 1, 0.15);
    for (double order : observed_orders(runs, &FluidityErrors::h1))
      EXPECT_NEAR(order, degree, 0.15);
  }
  // the profile itself: g_w at the walls, g_loc (1 - 1/cosh(5)) + g_w / cosh(5) at mid-height
  EXPECT_NEAR(planar_shear_profile(layer, 0.0), layer.g_wall, 1e-14);
  EXPECT_NEAR(planar_shear_profile(layer, layer.height), layer.g_wall, 1e-14);
  EXPECT_NEAR(planar_shear_profile(layer, 0.5), 2 - 1.5 / std::cosh(5.0), 1e-14);
}

// Zero flux on every boundary (the outer square and a circular hole, as around the intruder),
// uniform g_loc = 1.5 1/s and a variable xi: nothing drives a gradient, so g = g_loc exactly
// and the discrete solution must equal it to round-off: max nodal error below 1e-12 g_loc, with
// Q1 and Q2, on a curved mesh refined twice.
TEST(Fluidity, ZeroFluxWithUniformLocalFluidityGivesUniformFluidity) {
  for (int degree : {1, 2}) {
    const FluidityErrors r = uniform_zero_flux_fluidity(2, degree);
    std::printf("zero flux Q%d: %d cells, %d dofs, max |g_h - g_loc| = %.2e, L2 %.2e\n", degree,
                r.cells, r.dofs, r.max_nodal, r.l2);
    EXPECT_LT(r.max_nodal, 1e-12 * 1.5);
  }
}

// Manufactured solution with a variable cooperativity length, g = 2 + sin(pi x/2) cos(pi y),
// xi = 0.2 (1 + x y / 2) on the unit square, g imposed on two sides and zero flux on the other
// two: h = 1/4 to 1/32, every observed order of the L2 error within 0.15 of degree + 1 and of
// the H1 seminorm within 0.15 of degree.
TEST(Fluidity, ManufacturedVariableXiAtOptimalRates) {
  for (int degree : {1, 2}) {
    std::vector<FluidityErrors> runs;
    for (int refinement = 2; refinement <= 5; ++refinement)
      runs.push_back(manufactured_fluidity(refinement, degree));
    print_runs("manufactured", degree, runs);
    for (double order : observed_orders(runs, &FluidityErrors::l2))
      EXPECT_NEAR(order, degree + 1, 0.15);
    for (double order : observed_orders(runs, &FluidityErrors::h1))
      EXPECT_NEAR(order, degree, 0.15);
  }
}

// The capped cooperativity length (fluidity_law.h), with mu_s = 0.38, A = 0.5,
// d = 1 mm and xi_max = 50 d (so eps = (A d / xi_max)^2 = 1e-4): xi = xi_max at mu = mu_s to
// 1e-14, xi <= xi_max and symmetric about mu_s everywhere, xi falling as |mu - mu_s| grows,
// and within (eps / |mu - mu_s|)^2 / 4 below the law A d / sqrt|mu - mu_s| (below 2.5e-7 of
// it at |mu - mu_s| >= 0.1).
TEST(Fluidity, CooperativityLengthIsCappedNearTheYieldRatio) {
  const double mu_s = 0.38, A = 0.5, d = 1e-3, xi_max = 50 * d, eps = 1e-4;
  EXPECT_NEAR(grainlift::cooperativity_length(mu_s, mu_s, A, d, xi_max), xi_max, 1e-14 * xi_max);
  double previous = xi_max;
  for (int k = 1; k <= 400; ++k) {
    const double dmu = 1e-6 * std::pow(1.05, k);  // 1e-6 ... 0.3
    const double above = grainlift::cooperativity_length(mu_s + dmu, mu_s, A, d, xi_max);
    const double below = grainlift::cooperativity_length(mu_s - dmu, mu_s, A, d, xi_max);
    EXPECT_LE(above, xi_max);
    EXPECT_NEAR(above, below, 1e-14 * xi_max);
    EXPECT_LT(above, previous);
    previous = above;
    const double law = A * d / std::sqrt(dmu);
    const double deficit = 1 - above / law;
    EXPECT_GE(deficit, -1e-14);
    EXPECT_LE(deficit, 0.25 * (eps / dmu) * (eps / dmu) + 1e-14);
    if (dmu >= 0.1) {
      EXPECT_LT(deficit, 2.5e-7);
    }
  }
}

// The flow step's stress ratio (fluidity_law.h): gamma_dot = mu (g_loc(mu, p) + excess) has one
// root wherever g_loc + excess stays positive, so mu -> gamma_dot -> mu must return mu on every
// branch: below yield (g_loc = 0, excess > 0), on Jop's inverse law (excess of either sign,
// down to -0.9 g_loc) and above the cap I = 1 (g_loc constant). Jop's glass beads (mu_s 0.38,
// mu_2 0.64, I0 0.279, rho_s 2500, d 0.02 m), p = 2000 Pa: mu back to 1e-12, and d mu /
// d gamma_dot and d mu / dp within 1e-5 of central differences.
TEST(Fluidity, StressRatioAtFluidityInvertsTheFlowRule) {
  const grainlift::FluidityMaterial m{0.38, 0.64, 0.279, 2500, 0.02};
  const double p = 2000;
  int checked = 0;
  for (double mu : {0.05, 0.2, 0.37, 0.381, 0.45, 0.55, 0.62, 0.635, 0.7, 1.2}) {
    const double g_loc = grainlift::local_fluidity(mu, p, m);
    for (double excess : {-0.9 * g_loc, -0.3 * g_loc, 0.0, 0.05, 2.0, 30.0}) {
      if (!(g_loc + excess > 0)) continue;  // no flow at this mu
      const double rate = mu * (g_loc + excess);
      const grainlift::FluidityStressRatio s =
          grainlift::stress_ratio_at_fluidity(rate, p, excess, m);
      EXPECT_NEAR(s.mu, mu, 1e-12) << "mu " << mu << " excess " << excess;
      const double h = 1e-6 * rate, hp = 1e-6 * p;
      const double d_rate = (grainlift::stress_ratio_at_fluidity(rate + h, p, excess, m).mu -
                             grainlift::stress_ratio_at_fluidity(rate - h, p, excess, m).mu) /
                            (2 * h);
      const double d_p = (grainlift::stress_ratio_at_fluidity(rate, p + hp, excess, m).mu -
                          grainlift::stress_ratio_at_fluidity(rate, p - hp, excess, m).mu) /
                         (2 * hp);
      EXPECT_NEAR(s.dmu_drate, d_rate, 1e-5 * std::abs(d_rate) + 1e-12) << mu << " " << excess;
      EXPECT_NEAR(s.dmu_dp, d_p, 1e-5 * std::abs(d_p) + 1e-12) << mu << " " << excess;
      ++checked;
    }
  }
  EXPECT_GE(checked, 40);
}
