// DEM simple-shear cell at imposed pressure (GDR MiDi 2004; da Cruz et al., PRE 72, 021309
// (2005)): grains between two rough walls of frozen disks, periodic in x; the bottom wall is
// fixed, the top wall is a PressureLid pushed down with P and moved along x at the speed U. The
// steady state gives one point of the rheology: mu = tau / P and the area fraction Phi against
// the inertial number I = gamma_dot d / sqrt(P / rho_s), gamma_dot measured from the velocity
// profile of the bulk. No intruder. With gravity across the layer (ShearCellConfig::gravity,
// the creeping-layer cell of `grainlift calibrate --nonlocal`) the pressure grows with depth at
// a uniform shear stress, so mu = tau / p falls below the yield ratio under the sheared top and
// the grains there creep. See docs/dem-model.md, "Simple-shear cell".
#pragma once

#include <cstddef>
#include <vector>

#include "grainlift/dem/dem_config.h"

namespace grainlift::dem {

/// A window mean and its standard error (same units as the series): the block mean of
/// shared/include/grainlift/shared/statistics/statistics.h (the first samples left over dropped)
/// with its correlation-corrected error (stderr_corrected).
struct MeanError {
  double mean = 0;
  double se = 0;  ///< standard error of the mean
};

struct ShearCellConfig {
  /// The grains and the run control: grain_diameter, polydispersity, density (rho_s, kg/m^2),
  /// contact, dt, seed, threads, packing_cache_dir, area_fraction (of the prepared bed, before
  /// the lid loads it), relax_ke_per_grain, max_overlap_fraction. The box, walls, gravity,
  /// intruder and lid fields are set by the cell.
  DemConfig grains;
  double width = 20;    ///< W, in mean diameters (the period in x)
  double height = 20;   ///< H, in mean diameters: box height at preparation (wall disks included)
  double pressure = 0;  ///< P, N/m (2D units), on the lid
  double wall_speed = 0;  ///< U, m/s: x speed of the lid (the bottom wall is at rest)
  long long run_in_steps = 0;      ///< steps before the first measurement window
  long long measure_steps = 0;     ///< steps of a measurement window
  long long max_run_in_steps = 0;  ///< cap of the extended run-in (0: run_in_steps, no extension)
  int sample_every = 20;           ///< steps between samples
  int blocks = 10;                 ///< blocks of the window (even, >= 4) for the standard errors
  double wall_layer = 3;           ///< d: grains this close to a wall's centre line are not bulk
  /// Steady when the mean mu and Phi of the two halves of the window differ by at most this
  /// many combined standard errors.
  double steady_sigma = 2;
  /// m/s^2, gravity along -y (0: none). The pressure then grows from the lid's P downwards by
  /// the weight of the grains above (ShearCellResult::profile_pressure).
  double gravity = 0;
};

/// One sample (every sample_every steps).
struct ShearCellSample {
  double time = 0;          ///< s
  /// N/m, y force of the grains on the lid / W, averaged over the steps since the last sample
  double pressure = 0;
  double shear_stress = 0;  ///< N/m, tau on the lid: minus the grains' x force on it / W, the same
  /// N/m, tau on the bottom wall: the grains' x force on it / W at the sample's step
  double bottom_shear_stress = 0;
  /// N/m, the grains' downward force on the bottom wall / W at the sample's step (P plus the
  /// grains' weight per width under gravity)
  double bottom_pressure = 0;
  double lid_height = 0;    ///< m, lid centre line above the bottom wall's
  double area_fraction = 0; ///< of the bulk (grains with centres > wall_layer d from both walls)
};

struct ShearCellResult {
  std::vector<ShearCellSample> samples;  ///< the whole run, run-in included
  std::size_t window_begin = 0;          ///< first sample of the measurement window
  long long run_in_steps = 0;            ///< steps before the window (extended if not steady)
  long long steps = 0;                   ///< all steps
  bool steady = false;  ///< the halves of the window agreed (ShearCellConfig::steady_sigma)
  int grains = 0;
  double grain_mass = 0;  ///< kg (per metre of depth), all grains together
  double packed_area_fraction = 0;  ///< of the prepared bed, between fixed walls
  /// Velocity profile, time-averaged over the window's samples: bins of one d above the bottom
  /// wall's centre line (bin k: [k d, (k + 1) d)); vx the mean grain x velocity (m/s) in the bin.
  std::vector<double> profile_y;   ///< m, bin centres above the bottom wall's centre line
  std::vector<double> profile_vx;  ///< m/s (0 in an empty bin)
  std::vector<long long> profile_count;  ///< grain samples in the bin
  /// m/s, standard error of profile_vx: the block rule (statistics.h, ShearCellConfig::blocks)
  /// over the series of the bin's mean x velocity per sample (0 with fewer than 2 blocks)
  std::vector<double> profile_vx_stderr;
  /// m/s, the velocity fluctuation delta v of the bin: the square root of the window's mean of
  /// the grains' velocity variance about the bin's mean velocity (x and y), per sample; and its
  /// standard error (the block rule on the variance, propagated)
  std::vector<double> profile_dv, profile_dv_stderr;
  /// N/m, mean pressure at the bin centre: the lid's P plus gravity times the mean mass of the
  /// grains above that height per unit width (P everywhere without gravity)
  std::vector<double> profile_pressure;
  /// per bin, the mean local hexatic order |psi6| (bond_order.h) of its grains in the window's
  /// last state (NaN in a bin without a grain that has neighbours): near 1 where the layer has
  /// crystallised, lower where it is disordered
  std::vector<double> profile_psi6;
  /// Least-squares line vx = a + gamma_dot y through the bulk bins.
  double shear_rate = 0;       ///< 1/s, gamma_dot
  double profile_r2 = 0;       ///< coefficient of determination of the line
  double profile_max_deviation = 0;  ///< largest |vx - line| of a bulk bin / U (0 when U = 0)
  int bulk_bins = 0;
  /// Window means with block standard errors (ShearCellConfig::blocks).
  MeanError pressure, shear_stress, bottom_shear_stress, bottom_pressure, lid_height,
      area_fraction;
  MeanError friction;  ///< mu = tau / P, per block: the ratio of the block means
  double inertial_number = 0;  ///< gamma_dot d / sqrt(P / rho_s), P the window's mean
};

/// @brief Run the simple-shear cell: prepare (or load) the bed, attach the lid at P moving at
/// U, run run_in_steps, then measurement windows of measure_steps until the two halves of a
/// window agree (steady) or the run-in would pass max_run_in_steps; the last window is measured.
/// @param progress called with (fraction, "shear"); the packing reports (fraction, "packing").
/// @throws ConfigError for a bad configuration, RunFailure when the run blows up.
ShearCellResult run_shear_cell(const ShearCellConfig& cfg, const ProgressCallback& progress = {});

/// @brief @p base set up for one point of a rheology sweep at the target inertial number
/// @p target_I: the wall speed U = I gap sqrt(P / rho_s) / d (gap between the walls' centre
/// lines, so the nominal shear rate U / gap gives I), a run-in of strain 1 and a window of
/// strain 2 (half that below I = 0.01, for the cost), times @p strain_scale, a run-in that may
/// be extended by two windows until steady, and about 2,000 samples per window.
ShearCellConfig shear_cell_at(const ShearCellConfig& base, double target_I, double strain_scale);

/// @brief The DemConfig of the cell's bed and lid (box, walls, gravity, no intruder,
/// lid_pressure = P) from cfg.grains.
DemConfig shear_cell_dem_config(const ShearCellConfig& cfg);

}  // namespace grainlift::dem
