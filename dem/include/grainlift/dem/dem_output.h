// What one DEM run hands back to the glue, which turns it into the shared schema.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "grainlift/dem/bed/bed_fingerprint.h"

namespace grainlift::dem {

/// Force on the intruder at one sample time (lab frame, per unit length).
struct IntruderSample {
  double time = 0;      ///< s
  double fx = 0, fy = 0;  ///< N/m, total contact force exerted by the grains on the intruder
  double torque = 0;    ///< N, about the intruder centre, counter-clockwise positive
  int contacts = 0;     ///< number of grains touching the intruder
};

/// One grain-intruder contact at a sample time (only samples after the steady-state start).
struct IntruderContact {
  std::int32_t sample = 0;  ///< index into DemOutput::samples
  double theta = 0;   ///< rad, contact angle from +x, counter-clockwise, in (-pi, pi]
  double fn = 0;  ///< N/m, normal force on the intruder, positive when compressive (pushing inward)
  double ft = 0;      ///< N/m, tangential force on the intruder, positive counter-clockwise
  /// m/s, slip velocity: the intruder's surface relative to the grain's contact point,
  /// positive counter-clockwise (omega R - V sin(theta) for a grain at rest, not spinning)
  double vt = 0;
  bool slipping = false;  ///< |ft| reached mu |fn| (to relative 1e-9)
};

/// Coarse-grained fields in the intruder frame, averaged over the snapshots taken
/// after the steady-state start; row-major [j * nx + i] (j along y).
struct FieldAverages {
  int nx = 0, ny = 0, snapshots = 0;
  std::vector<double> area_fraction;            ///< Kumar eq. (A6)
  std::vector<double> vx, vy;                   ///< m/s, relative to the intruder, eq. (A3)-(A4)
  std::vector<double> granular_temperature;     ///< m^2/s^2, eq. (A7)
  std::vector<double> sxx, sxy,
      syy;  ///< Pa*m (2D stress, N/m), contact stress, compressive negative
};

/// The pressure-controlled lid at one force-sample time (DemConfig::lid_pressure > 0).
struct LidSample {
  double time = 0;      ///< s
  double y = 0;         ///< m, height of the lid disks' centres
  double pressure = 0;  ///< N/m, force of the grains on the lid / box width
};

/// The bed's stress away from the intruder at one force-sample time (far_field_stress.h).
struct FarFieldSample {
  double time = 0;                 ///< s
  double pressure = 0;             ///< N/m (2D pressure), -(sxx + syy) / 2
  double sxx = 0, sxy = 0, syy = 0;  ///< N/m, tension positive
  double area = 0;                 ///< m^2, the region measured
};

struct DemOutput {
  std::vector<IntruderSample> samples;
  std::vector<IntruderContact> contacts;  ///< after steady_start_index only
  std::size_t steady_start_index = 0;     ///< first sample used for averaging
  FieldAverages fields;                   ///< empty (nx == 0) when fields are off
  int grains = 0;                         ///< number of mobile grains
  int wall_grains = 0;
  double achieved_area_fraction = 0;
  double collision_time = 0;              ///< s, binary collision time used for the dt check
  bool packing_from_cache = false;
  /// Why the packing cache's entry was not used (damaged, foreign: removed, the bed rebuilt)
  std::string packing_cache_note;
  long long steps = 0;                    ///< steps run
  long long planned_steps = 0;            ///< steps of the whole travel
  bool frictionless_path =
      false;  ///< contacts by normal force only (mu = 0, DemConfig::frictionless_path)
  /// sleeping grains (DemConfig::sleep_speed >= 0): mean fraction of the grains asleep over
  /// the run's steps, grains woken by contact, list builds forced by a wake
  double sleeping_fraction = 0;
  long long sleep_wakes = 0;
  int sleep_wake_builds = 0;
  bool stopped_early = false;
  /// the prepared bed's structure at rest (bed_fingerprint.h); gap_fraction empty when not
  /// measured (a run resumed from a checkpoint)
  BedFingerprint bed;
  double bed_max_overlap = 0;  ///< largest overlap / smaller diameter of the prepared bed at rest
  double run_max_overlap = 0;  ///< the same, the largest the pair forces met during the run
  bool interrupted = false;    ///< ended by RunControl::interrupted (a checkpoint was taken)
  long long resumed_from_step = -1;  ///< the step of the checkpoint it went on from (-1: none) ///<
                                     ///< a RunMonitor ended the run before the travel
  int list_builds = 0;                    ///< Verlet-list builds during the run
  int threads_used = 1;                   ///< threads the step ran on (DemSystem::threads_used)
  int threads_allowed = 1;                ///< threads it could use (DemSystem::threads_allowed)
  long long steps_on_team = 0;            ///< steps run on threads_allowed (> 1) threads
  std::vector<LidSample> lid;             ///< one per force sample; empty without a lid
  double lid_mass = 0, lid_damping = 0;   ///< kg, kg/s: the lid actually used
  /// one per force sample when the per-pair forces are kept (fields or a lid); else empty
  std::vector<FarFieldSample> far_field;
  double far_field_exclusion = 0, far_field_half_height = 0;  ///< m, the region (FarFieldRegion)
};

}  // namespace grainlift::dem
