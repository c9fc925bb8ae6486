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

/// The stress ratio of a flow whose fluidity is the local one plus a given excess, and its
/// derivatives (the flow step of the continuum's splitting, nonlocal_coupling.cc).
struct FluidityStressRatio {
  double mu = 0;         ///< stress ratio
  double dmu_drate = 0;  ///< d mu / d gamma_dot (s)
  double dmu_dp = 0;     ///< d mu / d p (1/Pa)
};

/// @brief mu such that gamma_dot = mu (g_loc(mu, p) + @p excess), g_loc the local_fluidity()
/// above: the nonlocal model's gamma_dot = g mu with the local part of g taken at the flow's own
/// stress ratio and the nonlocal part (g - g_loc) given. h(mu) = mu (g_loc + excess) rises
/// wherever it is positive, so the root is unique when g_loc(mu_cap) + excess > 0 (the caller's
/// g is floored above 0); the pieces: mu <= mu_s (g_loc = 0: mu = gamma_dot / excess), the
/// inverse of Jop's law (a safeguarded Newton in I), mu >= mu(I_cap) (g_loc constant).
/// @param rate gamma_dot (1/s, > 0); p pressure (Pa, > 0); excess g - g_loc (1/s, any sign)
/// @return mu and its derivatives in @p rate and @p p at fixed @p excess; mu = 0 and zero
/// derivatives when @p rate or @p p is not positive or no root exists
FluidityStressRatio stress_ratio_at_fluidity(double rate, double p, double excess,
                                             const FluidityMaterial& m);

}  // namespace grainlift
