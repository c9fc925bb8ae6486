// The two laws of the nonlocal granular fluidity model (Kamrin & Koval, PRL 108, 178301, 2012;
// Henann & Kamrin, PNAS 110, 6730, 2013), written once for the continuum's fluidity equation
// g - xi^2 Laplacian(g) = g_loc and the calibration of A on a creeping layer. Pure functions.
#pragma once

namespace grainlift {

/// @brief Cooperativity length xi = A d / sqrt|mu - mu_s|, capped at the yield ratio:
///     xi = A d / ((mu - mu_s)^2 + eps^2)^(1/4),   eps = (A d / xi_max)^2,
/// so xi <= xi_max everywhere, xi = xi_max at mu = mu_s (the fluidity equation's diffusion
/// coefficient xi^2 stays bounded, its matrix well conditioned), xi is smooth in mu at mu_s too
/// (a hard min(law, xi_max) has a kink there, a smoothing on |mu - mu_s| a cusp; a Newton needs
/// dxi/dmu), and away from mu_s it is the law to second order: 0 <= 1 - xi / xi_law <=
/// (eps / |mu - mu_s|)^2 / 4 (below 2.5e-7 at |mu - mu_s| = 0.1 for xi_max = 100 A d). xi_max
/// is the caller's: a few tens of d, or the flow region's size (a longer xi has no effect).
/// @param mu stress ratio; mu_s yield ratio; A amplitude (> 0); d grain diameter (m, > 0);
/// xi_max the cap (m, > 0). @return xi (m)
double cooperativity_length(double mu, double mu_s, double A, double d, double xi_max);

/// Jop's mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1) and the grains it is measured on.
struct FluidityMaterial {
  double mu_s = 0, mu_2 = 0, I0 = 0;
  double solid_density = 0;   ///< rho_s (kg/m^3, or kg/m^2 in 2D)
  double grain_diameter = 0;  ///< m
};

/// Largest inertial number of local_fluidity(): uncapped, the pole of I(mu) at mu_2 made the
/// continuum's splitting swing between g -> infinity and g -> 0 (nonlocal_coupling.cc).
constexpr double kMaxLocalFluidityInertial = 1.0;

/// @brief The local fluidity g_loc = gamma_dot / mu = I sqrt(p / rho_s) / (d mu) (1/s) at stress
/// ratio @p mu and pressure @p p, with I(mu) = I0 (mu - mu_s) / (mu_2 - mu) the inverse of
/// Jop's law for mu > mu_s (0 below or where p <= 0), capped at I = min(1, 999 I0).
double local_fluidity(double mu, double p, const FluidityMaterial& m);

}  // namespace grainlift
