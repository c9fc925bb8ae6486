// Plain-data description of one DEM run, filled from the case file by the glue in
// dem/glue/dem_solver.cc. No I/O, no TOML, no HDF5 here: the engine sees only numbers.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>

namespace grainlift::dem {

/// Which contact law is used for every contact (grain-grain, grain-wall, grain-intruder).
enum class ContactLaw {
  kumar2019,    ///< Kumar 2019 eq. (1)-(2), Table I: Hertz with history, Kn, Kt, gamma_n, gamma_t.
  guillard2014  ///< Guillard 2014 Table I: Hertz from E, nu, restitution e.
};

/// Material parameters of the contact law (a "species"; per-contact history lives elsewhere).
/// How a dense bed is made (packing.cc, docs/dem-model.md "Bed preparation").
enum class Preparation {
  radius_growth,     ///< inserted at reduced radii, frictionless growth in place (fast)
  wall_compression   ///< Kumar 2019: full size in a taller box, the top wall closes slowly
};

struct ContactParams {
  ContactLaw law = ContactLaw::kumar2019;
  double kn = 2e9;        ///< Pa, Kumar Table I (F_n = sqrt(R_eff delta) Kn delta)
  double kt = 2.45e9;     ///< Pa, Kumar Table I
  double gamma_n = 8e6;   ///< 1/(m s), Kumar Table I
  double gamma_t = 8e6;   ///< 1/(m s), Kumar Table I
  double youngs_modulus = 5e6;  ///< Pa, Guillard Table I
  double poisson_ratio = 0.45;  ///< -, Guillard Table I
  double restitution = 0.6;     ///< -, Guillard Table I
  double friction = 0.5;        ///< Coulomb coefficient mu between grains (and grain-wall)
  double intruder_friction = 0.5;  ///< Coulomb coefficient between grains and the intruder
};

/// Regular grid in the intruder frame on which fields are coarse-grained.
/// Cell (i, j) covers [x0 + i h, x0 + (i+1) h] x [y0 + j h, y0 + (j+1) h], coordinates
/// relative to the intruder centre, x along the direction of motion when V is along +x.
struct FieldGridSpec {
  bool enabled = false;
  double x0 = 0, y0 = 0;   ///< m, lower-left corner relative to the intruder centre
  double spacing = 0;      ///< m, square bin size
  int nx = 0, ny = 0;
};

struct DemConfig {
  // ---- domain (lab frame, m)
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  bool periodic_x = true, periodic_y = false;
  /// Frozen-disk walls (disks of the mean diameter, centres d/2 inside the box edge).
  bool wall_bottom = false, wall_top = false, wall_left = false, wall_right = false;
  std::array<double, 2> gravity{0, 0};  ///< m/s^2
  /// Pressure-controlled lid (lid.h): > 0 makes the top wall a rigid lid pushed down with
  /// lid_pressure * (xmax - xmin). N/m in the engine's units (force per lid length; the glue's
  /// 2D reading: Pa). 0: the top wall is fixed. Needs wall_top and !periodic_y.
  double lid_pressure = 0;
  double lid_mass = 0;     ///< kg; 0 = PressureLid::default_mass (the mass of the bed)
  double lid_damping = 0;  ///< kg/s; 0 = PressureLid::default_damping (critical)
  /// false: the lid is one rigid body; true: each lid disk rises and sinks on its own under its
  /// share P W / N of the load, with mass M / N and damping c / N (Guillard 2014's heavy lid of
  /// free-to-rise disks, horizontal velocity imposed)
  bool lid_free_disks = false;

  // ---- grains
  double grain_diameter = 0.02;   ///< m, mean
  double polydispersity = 0.1;    ///< relative half-width of the uniform diameter distribution
  double density = 20;            ///< kg/m^2: 2D mass per area (Kumar Table I)
  double area_fraction = 0.8;     ///< target Phi of the bed (grains only, intruder area excluded)
  ContactParams contact;

  // ---- intruder (a disk with prescribed motion)
  double intruder_diameter = 0.1;       ///< m
  std::array<double, 2> intruder_position{0, 0};  ///< m, at t = 0
  std::array<double, 2> intruder_velocity{1, 0};  ///< m/s
  double intruder_omega = 0;            ///< rad/s, counter-clockwise positive
  double spin_ramp_time = 0;  ///< s, omega ramps linearly from 0 over this time (0: at once)

  // ---- run control
  double dt = 2e-6;                ///< s
  double max_dt_fraction = 0.1;    ///< refuse dt above this fraction of the binary collision time
  double travel = 300;             ///< total intruder travel, in mean grain diameters
  double steady_travel = 30;       ///< travel before averaging starts, in mean grain diameters
  std::uint64_t seed = 1;
  int sample_every = 50;           ///< steps between force samples
  int threads = 1;
  double relax_ke_per_grain = 1e-9;  ///< J: packing relaxed until mean KE per grain is below
  /// how a bed above Phi 0.4 is made (packing.h): radius growth in place, or Kumar 2019's
  /// closing top wall at compression_speed (m/s)
  Preparation preparation = Preparation::radius_growth;
  double compression_speed = 0.2;
  /// wall_compression: the walls close under the relaxation's background drag 1/(2000 dt)
  /// (true), or with contact damping only (false: a more uniform bed)
  bool compression_drag = true;
  std::string packing_cache_dir;   ///< where prepared beds are saved and reused ("" = no cache)
  FieldGridSpec fields;            ///< coarse-grained fields (off: bit-identical forces)
  int field_every = 500;           ///< steps between field snapshots (after the steady state)
  /// with contact.friction = 0: contacts by their normal force only (no tangential
  /// kinematics or history; the same trajectories, DemSystem::set_frictionless_path)
  bool frictionless_path = true;
  /// m/s: grains at most this fast, at rest and far from the intruder, sleep
  /// (DemSystem::set_sleep); 0: only grains exactly at rest; < 0: no sleeping
  double sleep_speed = 0;
  /// steps between renumberings of the grains into rows of cells (DemSystem's sort_every;
  /// 0: never)
  long long sort_every = 0;

  // ---- added by the DEM engine (defaults keep the meaning of the fields above)
  /// m/s, impact speed of the binary collision time used for the dt check;
  /// 0 = the intruder's fastest surface speed |V| + |omega| R.
  double dt_check_velocity = 0;
  /// A run fails (RunFailure) when an overlap exceeds this fraction of the smaller diameter.
  double max_overlap_fraction = 0.1;
};

/// Progress report: fraction done in [0, 1] and a short phase name ("packing", "run").
using ProgressCallback = std::function<void(double fraction, const char* phase)>;

}  // namespace grainlift::dem
