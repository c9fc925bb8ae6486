// The amplitude A of the nonlocal granular fluidity model's cooperativity length
// xi = A d / sqrt|mu - mu_s| (Kamrin & Koval, PRL 108, 178301, 2012), measured on a layer sheared
// at its top under gravity: the shear stress tau is uniform and the pressure grows with depth, so
// mu = tau / p falls through mu_s and a local law would stop the flow there; cooperativity
// carries it into the bed below, the further the larger A. In one dimension the fluidity obeys
//   g - xi(mu)^2 g'' = g_loc(mu, p),   g' = 0 at both walls,
// (fluidity_law.h: the continuum's laws), linear in g for the measured p(y), and the velocity
// is v(y) = v_floor + C integral of mu g dy. The fit solves it for each A (d / 32 cells, a
// tridiagonal solve), averages v over each bin and takes v_floor and C by weighted linear least
// squares; A by a scan of ln A and a golden section, its error where chi2 rises by
// max(1, chi2/dof). C = 1 when the calibrated mu(I) holds in the flowing layer. Pure functions.
#pragma once

#include <string>
#include <vector>

#include "grainlift/shared/rheology/fluidity_law.h"

namespace grainlift {

/// A steady profile across the sheared layer (bins along y, measured from the bottom wall).
struct CreepProfile {
  std::vector<double> y;         ///< m, bin centres, increasing, evenly spaced
  std::vector<double> vx;        ///< m/s, mean velocity along the shear direction
  std::vector<double> vx_err;    ///< m/s, its standard error (> 0 where used)
  std::vector<double> pressure;  ///< mean pressure at the bin centre (tau's unit)
  /// m/s, the grains' velocity fluctuation about the bin's mean and its error (reported, not
  /// fitted; empty or of y's length)
  std::vector<double> dv, dv_err;
  /// the grains' mean local hexatic order |psi6| per bin (reported, not fitted; empty or of y's
  /// length; NaN where unmeasured): near 1 where the layer has crystallised
  std::vector<double> psi6;
  double shear_stress = 0;       ///< tau, uniform across the layer
  double shear_stress_err = 0;
  double bottom = 0, top = 0;    ///< m, the walls (g' = 0 there)
  double y_min = 0, y_max = 0;   ///< m, bins outside [y_min, y_max] are not fitted (wall layers)
};

struct CooperativityFitOptions {
  double a_min = 0.01, a_max = 10;  ///< the range of A searched
  double xi_max = 0;  ///< m, the cap of xi at mu_s (0: the layer's height top - bottom)
  /// A is not determined when C lies outside [1 / scale_range, scale_range]: the calibrated
  /// mu(I) does not describe the layer's flow, and the shape A is fitted to is not the model's
  double scale_range = 3;
};

/// The fitted amplitude, one-sigma errors.
struct CooperativityFit {
  double amplitude = 0;       ///< A
  double amplitude_err = 0;   ///< total: the profile's error and those of mu_s and tau
  double profile_err = 0;     ///< the profile's own (chi2 rise of max(1, chi2/dof))
  double mu_s_err_part = 0;   ///< half the change of A when mu_s moves by +- its error
  double scale = 0;           ///< C: the measured velocity over the calibrated law's
  double floor = 0;           ///< m/s, v_floor (slip at the bottom wall)
  double chi2_per_dof = 0;
  int points = 0;             ///< bins fitted
  double mu_min = 0, mu_max = 0;  ///< range of mu = tau / p over them
  /// one-sigma upper bound of A when chi2 is least at a_min (then ok = false)
  double upper_bound = 0;
  bool ok = false;
  std::string message;        ///< why not, when !ok
};

/// @brief The model's velocity per bin of @p profile at amplitude @p A (C = 1, v_floor = 0),
/// xi capped at @p xi_max (m; 0: the layer's height top - bottom, as the fit's default).
std::vector<double> fluidity_velocity(const CreepProfile& profile, const FluidityMaterial& law,
                                      double A, double xi_max);

/// @brief Fits A on @p profile with the calibrated mu(I) @p law of the same grains (mu_s known to
/// +- @p mu_s_err). The bins' errors are taken as independent.
/// @throws std::invalid_argument when the profile's arrays differ in length, fewer than 5 bins
///         are fitted, or the law or the walls are not usable.
CooperativityFit fit_cooperativity(const CreepProfile& profile, const FluidityMaterial& law,
                                   double mu_s_err, const CooperativityFitOptions& options = {});

}  // namespace grainlift
