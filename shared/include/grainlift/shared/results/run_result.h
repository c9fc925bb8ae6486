// The in-memory image of one solver's output file <out>/<solver>.h5 (see docs/schema.md).
// Every optional block is absent from the file when the solver could not produce it:
// absent, never filled with zeros.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace grainlift {

/// Who produced the file, how, and from which case.
struct RunMetadata {
  std::string solver;            ///< "dem" or "fem"
  std::string grainlift_version;
  std::string git_revision;
  int threads = 1;
  double wall_seconds = 0;       ///< s, whole run including set-up
  std::string created_utc;       ///< ISO 8601
  std::string case_text;         ///< the case file verbatim
  std::string case_overrides;    ///< the --set overrides, one "key=value" per line
  std::string case_hash;         ///< FNV-1a 64 of case_text + "\n--\n" + case_overrides, hex
  std::string case_path;
  std::string notes;             ///< free text: convergence, packing cache, warnings
  /// the run was interrupted (Ctrl-C, SIGTERM) and holds what it had so far: complete
  /// files, shorter series; `grainlift run CASE --resume DIR` goes on (DEM)
  bool partial = false;
};

/// Geometry shared by both solvers (SI units, lab frame at t = 0).
struct Geometry {
  double intruder_diameter = 0;   ///< m
  double intruder_x = 0, intruder_y = 0;  ///< m
  double grain_diameter = 0;      ///< m, mean
  double domain_xmin = 0, domain_xmax = 0, domain_ymin = 0, domain_ymax = 0;  ///< m
  double velocity_x = 0, velocity_y = 0;  ///< m/s, intruder velocity V
  double omega = 0;               ///< rad/s, counter-clockwise positive
  double gravity_x = 0, gravity_y = 0;    ///< m/s^2
  double bulk_density = 0;        ///< kg/m^3 (2D: per unit length), rho = Phi rho_s
  double pressure_scale = 0;      ///< Pa, the stated pressure scale P0 used to normalise stresses
  double reference_gravity = 0;   ///< m/s^2, |g| of the pressure scale (the lid's in lid_only mode)
  double equivalent_depth = 0;    ///< m, h = P0 / (rho g) of the case (0 without gravity)
};

/// Force on the intruder against time (per unit length, lab frame). A steady FE solution
/// is a single row.
struct ForceSeries {
  std::vector<double> time;       ///< s
  std::vector<double> fx, fy;     ///< N/m
  std::vector<double> torque;     ///< N (per unit length: N m / m)
  std::vector<double> contacts;   ///< count; empty when the solver has no contacts (FE)
};

/// Mean drag, lift and torque with standard errors (docs/conventions.md).
struct MeanForces {
  double drag = 0, lift = 0, torque = 0;        ///< N/m, N/m, N
  std::optional<double> drag_stderr, lift_stderr, torque_stderr;  ///< block-average standard errors
  std::optional<double> contacts;               ///< mean contact count (DEM)
  std::int64_t samples = 0;                     ///< samples averaged (1 for a steady FE solution)
  std::int64_t blocks = 0;                      ///< blocks used for the standard errors
};

/// The DEM's pressure-controlled lid (domain.lid_pressure > 0) against time.
struct LidSeries {
  std::vector<double> time;      ///< s
  std::vector<double> y;         ///< m, height of the lid disks' centres
  std::vector<double> pressure;  ///< Pa (2D reading), force of the grains on the lid / box width
  double target = 0;             ///< Pa, domain.lid_pressure
  double mean = 0;               ///< Pa, mean pressure after the steady-state start
  std::optional<double> mean_stderr;  ///< Pa, block-average standard error of mean
  double mass = 0, damping = 0;  ///< kg (per unit depth), kg/s: the lid's equation of motion
};

/// The DEM bed's own stress away from the intruder against time: contact plus kinetic stress
/// over a horizontal strip at the intruder's height, outside a disk around it (docs/schema.md).
struct FarFieldSeries {
  std::vector<double> time;                           ///< s
  std::vector<double> pressure;                       ///< Pa (2D reading), -(sxx + syy) / 2
  std::vector<double> stress_xx, stress_xy, stress_yy;  ///< Pa, tension positive
  double mean = 0;                     ///< Pa, mean pressure after the steady-state start
  std::optional<double> mean_stderr;   ///< Pa, its block-average standard error
  double exclusion = 0;                ///< m, radius of the disk around the intruder left out
  double half_height = 0;              ///< m, half height of the strip
};

/// Surface stress on the shared angle grid theta_m = (m + 1/2) 2 pi / M (Guillard eq. A4),
/// theta measured from the direction of V, counter-clockwise.
struct SurfaceDistribution {
  std::vector<double> theta;      ///< rad
  std::vector<double> sigma_n;    ///< Pa, compressive positive
  std::vector<double>
      sigma_t;  ///< Pa, positive when the medium pulls the surface counter-clockwise
  double kernel_width_deg = 0;    ///< Gaussian standard deviation (deg), output.kernel_width_deg
  /// The continuum's pointwise trace at theta before the kernel (Pa); absent for the DEM,
  /// whose surface stress exists only as the kernel average of its contacts.
  std::optional<std::vector<double>> sigma_n_pointwise, sigma_t_pointwise;
  /// Pa, DEM: the standard error of sigma_n, sigma_t at each angle, from the profiles of the
  /// same blocks as the forces' standard errors (block_mean over the blocks' values).
  std::optional<std::vector<double>> sigma_n_stderr, sigma_t_stderr;
};

/// Histogram of intruder contacts in equal bins (Kumar 2019 Fig. 6, pi/12 bins), DEM only.
struct SurfaceHistogram {
  std::vector<double> theta_lo, theta_hi;  ///< rad, bin edges, theta from the direction of V
  std::vector<double> contact_count;  ///< mean number of contacts in the bin per sample
  std::vector<double> normal_force;   ///< N/m, mean summed F_N in the bin per sample
  std::vector<double> tangential_force;  ///< N/m, mean summed F_T per sample (ccw positive)
  std::vector<double> slip_fraction;  ///< fraction of contacts in the bin with |F_T| = mu |F_N|
  /// m/s, mean slip velocity of the bin's contacts (the intruder's surface against the grain's
  /// contact point, ccw positive); absent where the contacts carry none (a LAMMPS import)
  std::optional<std::vector<double>> slip_velocity;
};

/// Fields on a regular grid in the intruder frame; each field may be absent independently.
/// Arrays are row-major [j * nx + i] with j along y. Cell centres x_i, y_j.
struct FieldGrid {
  std::vector<double> x, y;       ///< m, cell-centre coordinates relative to the intruder centre
  std::optional<std::vector<double>> velocity_x, velocity_y;  ///< m/s, intruder frame
  std::optional<std::vector<double>> pressure;                ///< Pa
  std::optional<std::vector<double>> stress_xx, stress_xy, stress_yy;  ///< Pa, tension positive
  std::optional<std::vector<double>> area_fraction;
  std::optional<std::vector<double>> granular_temperature;    ///< m^2/s^2
};

/// The DEM's prepared bed at rest, before the intruder moves (/bed; dem/.../bed_fingerprint.h):
/// a fingerprint of how the bed was made (issue 17).
struct BedStructure {
  double contacts_per_grain = 0;  ///< touching neighbours (grains, wall disks) per mobile grain
  double rattler_fraction = 0;    ///< mobile grains with fewer than 2 contacts
  double fabric_xx = 0, fabric_xy = 0, fabric_yy = 0;  ///< <n n> over grain-grain contacts
  double mean_gap = 0;            ///< mean gap to the nearest neighbour, mean diameters
  std::vector<double> gap_edges;     ///< mean diameters, n + 1 bin edges
  std::vector<double> gap_fraction;  ///< fraction of grains whose nearest gap is in each bin (n)
  std::vector<double> band_y, band_area_fraction;  ///< m, -: bands across the box
  std::vector<double> ring_r, ring_area_fraction;  ///< m, -: rings round the intruder's start
};

/// Solver diagnostics (/diagnostics): how the run went, as typed values a script reads by name
/// (docs/schema.md lists every name each solver writes), never parsed out of meta.notes.
struct Diagnostics {
  std::map<std::string, long long> counts;  ///< int64 attributes (iterations, cells, steps)
  std::map<std::string, double> values;     ///< float64 attributes (residuals, shares, seconds)
  std::map<std::string, std::string> texts; ///< string attributes (e.g. the linear solver)
  std::map<std::string, std::vector<double>> series;  ///< float64 datasets (residual history)
  bool empty() const { return counts.empty() && values.empty() && texts.empty() && series.empty(); }
};

/// Everything one solver writes.
struct RunResult {
  RunMetadata meta;
  Geometry geometry;
  std::optional<ForceSeries> forces;
  std::optional<MeanForces> means;
  std::optional<SurfaceDistribution> surface;
  std::optional<SurfaceHistogram> histogram;
  std::optional<FieldGrid> fields;
  std::optional<LidSeries> lid;
  std::optional<FarFieldSeries> far_field;
  std::optional<BedStructure> bed;
  Diagnostics diagnostics;
};

}  // namespace grainlift
