// `grainlift calibrate`: the mu(I) and Phi(I) of a case's grains, measured in the DEM
// simple-shear cell (dem/include/grainlift/dem/shear_cell.h) at imposed pressure and fitted
// (shared/include/grainlift/shared/rheology/rheology_fit.h), for the continuum to use the DEM's
// material (continuum.rheology_file).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "grainlift/dem/scenes/shear_cell.h"
#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/rheology/cooperativity_fit.h"
#include "grainlift/shared/rheology/rheology_file.h"

namespace grainlift::dem {

struct CalibrationOptions {
  /// P of the cell (Pa, 2D reading); 0: the case's confining pressure at the intruder (lid plus
  /// lithostatic), else continuum.ambient_pressure.
  double pressure = 0;
  /// Target inertial numbers (default: 8 from 1e-3 to 0.5).
  std::vector<double> inertial_numbers = {1e-3, 3e-3, 1e-2, 3e-2, 0.06, 0.1, 0.2, 0.5};
  double strain_scale = 1;  ///< multiplies the strain of each point's run-in and window
  double width = 20, height = 20;  ///< cell size, mean grain diameters
  int threads = 1;
  /// Points whose bulk velocity profile is not linear (R^2 below this) are shear-banded:
  /// reported, kept in the file, left out of the fit.
  double min_profile_r2 = 0.9;
};

/// One measured point of the sweep and how far to trust it.
struct CalibrationPoint {
  double target_I = 0;
  ShearPoint point;       ///< measured I, mu, Phi with standard errors
  bool steady = false;    ///< the two halves of the window agreed
  double profile_r2 = 0;  ///< linearity of the bulk velocity profile
  bool fitted = false;    ///< used in the fit (linear profile)
  /// Why the cell stopped ("" when it ran): a point the DEM cannot run at this dt (too fast
  /// for its grains) is reported and left out of the fit, not the end of the calibration.
  std::string failure;
  double wall_seconds = 0;
};

struct Calibration {
  std::vector<CalibrationPoint> points;
  RheologyFile law;  ///< fitted to the points with fitted = true
};

/// @brief The shear cell of the case's grains (size distribution, density, contact law,
/// friction, dt, seed, packing cache; make_dem_config) at @p pressure (Pa, 2D; 0: the case's
/// continuum_pressure()), @p width x @p height grain diameters, no wall speed or run yet.
/// @throws InputError naming the case when no pressure is known.
ShearCellConfig case_shear_cell(const Case& c, double pressure, int threads, double width,
                                double height);

/// @brief Run the shear cell on the case's grains (size distribution, density, contact law,
/// friction, dt, seed, packing cache) at each target I and fit mu(I), Phi(I).
/// @param say  one line per point (and warnings)
/// @throws InputError when no pressure is known or too few points have a linear profile (a
/// point whose cell fails, e.g. overlaps at a high I, counts as one without).
Calibration calibrate_rheology(const Case& c, const CalibrationOptions& options,
                               const std::function<void(const std::string&)>& say);

/// The creeping-layer cell of the cooperativity calibration: the shear cell with gravity across
/// the layer, tall enough that a bed under the sheared top creeps (mu = tau / p < mu_s).
struct CreepOptions {
  double pressure = 0;      ///< P on the lid, as CalibrationOptions::pressure
  double width = 20, height = 40;  ///< mean grain diameters
  double bottom_pressure_ratio = 3;  ///< p at the bottom wall / P: sets the gravity
  /// U = top_inertial_number sqrt(P / rho_s) times 10 (a flowing layer of about 10 d at the
  /// top's inertial number)
  double top_inertial_number = 0.05;
  double run_in_travel = 300;   ///< d the lid moves before the window
  double window_travel = 1500;  ///< d the lid moves in the window
  int threads = 1;
  /// independent beds (seeds dem.seed, + 1, ...) whose profiles are pooled bin by bin
  /// (statistics.h's pooled_mean: the larger of the beds' scatter and their own errors)
  int seeds = 4;
  CooperativityFitOptions fit;
};

struct CreepCalibration {
  std::vector<ShearCellResult> cells;  ///< one per seed
  CreepProfile profile;  ///< the beds' profiles pooled bin by bin (pressure with depth, errors)
  /// The result: with two or more beds all fitted, A is their pooled mean (statistics.h's
  /// pooled_mean: the larger of the beds' scatter and their own errors) and amplitude_err adds
  /// mu_s's part in quadrature; chi2_per_dof, scale, points and the mu range are the pooled
  /// profile's fit. With one bed, or a bed not fitted, the pooled profile's fit.
  CooperativityFit fit;
  double profile_fit_amplitude = 0;  ///< A of the pooled profile's fit (also when fit is the beds')
  /// m/s per bin of profile: v_floor + C times the model's velocity at the pooled profile's A,
  /// and at the local limit (A = fit options' a_min) with the same v_floor and C
  std::vector<double> fit_velocity, local_velocity;
};

/// @brief Run the creeping-layer cell on the case's grains and fit the cooperativity amplitude
/// A of xi = A d / sqrt|mu - mu_s| (cooperativity_fit.h) with the calibrated mu(I) @p law of the
/// same grains (their rheology file; mu_s's error enters A's).
/// @throws InputError when no pressure is known or the cell's configuration is refused;
///         RunError when the cell fails.
CreepCalibration calibrate_cooperativity(const Case& c, const CreepOptions& options,
                                         const MuIFit& law,
                                         const std::function<void(const std::string&)>& say);

}  // namespace grainlift::dem
