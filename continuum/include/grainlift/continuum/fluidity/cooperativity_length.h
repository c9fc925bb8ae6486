// The cooperativity length of the nonlocal granular fluidity model (Kamrin & Koval, PRL 108,
// 178301, 2012; Henann & Kamrin, PNAS 110, 6730, 2013), with a cap at the yield ratio mu_s.
// A pure function: no deal.II, no I/O.
#pragma once

namespace grainlift::continuum::fluidity {

/// @brief Cooperativity length xi(mu) of the fluidity equation g - xi^2 Laplacian(g) = g_loc.
///
/// The law is xi = A d / sqrt(|mu - mu_s|) (Henann & Kamrin 2013), which diverges at
/// the yield ratio mu = mu_s. **Cap rule**: the divergence is smoothed on (mu - mu_s)^2,
///
///     xi = A d / ((mu - mu_s)^2 + eps^2)^(1/4),   eps = (A d / xi_max)^2,
///
/// so that
///  - xi <= xi_max everywhere, with xi = xi_max exactly at mu = mu_s (the diffusion coefficient
///    xi^2 of the fluidity equation stays bounded by xi_max^2, the stiffness matrix stays
///    well conditioned);
///  - xi is C-infinity in mu, at mu_s included (a hard min(law, xi_max) has a kink, and the
///    smoothing on |mu - mu_s| has a cusp there; the later monolithic Newton needs dxi/dmu);
///  - away from mu_s it is the law to second order: 0 <= 1 - xi / xi_law <= (eps / |mu - mu_s|)^2
///    / 4 (Bernoulli), e.g. below 2.5e-7 at |mu - mu_s| = 0.1 for xi_max = 100 A d.
/// xi_max is a length the caller chooses (a few tens of grain diameters, or the size of the
/// domain: a cooperative length longer than the flow region has no effect beyond it).
/// @param mu stress ratio |tau| / p (dimensionless)
/// @param mu_s static friction coefficient of the mu(I) law (dimensionless)
/// @param A nonlocal amplitude (dimensionless, > 0, of order 1; a material constant)
/// @param d grain diameter (m, > 0)
/// @param xi_max the cap (m, > 0)
/// @return xi (m)
double xi_of_mu(double mu, double mu_s, double A, double d, double xi_max);

}  // namespace grainlift::continuum::fluidity
