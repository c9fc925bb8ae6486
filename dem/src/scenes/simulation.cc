// run_simulation: validation, bed, time loop with force sampling, contacts and fields.
#include "grainlift/dem/scenes/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "grainlift/dem/system/checkpoint.h"
#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/measure/far_field_stress.h"
#include "grainlift/dem/measure/field_accumulator.h"
#include "grainlift/dem/boundaries/lid.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/system/system_setup.h"
#include "scenes/message_number.h"

namespace grainlift::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void refuse(const std::string& what) { throw ConfigError(what); }

using detail::str;

/// " at (x, y) m, v (vx, vy) m/s" of grain g, for failure messages.
std::string describe_grain(const DemSystem& s, int g) {
  if (g < 0) return "";
  const ParticleArrays& p = s.particles();
  return " at (" + str(p.x[g]) + ", " + str(p.y[g]) + ") m, v (" + str(p.vx[g]) + ", " +
         str(p.vy[g]) + ") m/s";
}

double impact_speed(const DemConfig& c) {
  if (c.dt_check_velocity > 0) return c.dt_check_velocity;
  return std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]) +
         std::abs(c.intruder_omega) * 0.5 * c.intruder_diameter;
}

}  // namespace

double validate_config(const DemConfig& c) {
  if (!(c.xmax > c.xmin) || !(c.ymax > c.ymin)) {
    refuse("box [" + str(c.xmin) + ", " + str(c.xmax) + "] x [" + str(c.ymin) + ", " +
           str(c.ymax) + "] m is empty: need xmax > xmin and ymax > ymin");
  }
  if (!(c.grain_diameter > 0)) refuse("grain_diameter = " + str(c.grain_diameter) + " m: need > 0");
  if (!(c.polydispersity >= 0 && c.polydispersity < 1)) {
    refuse("polydispersity = " + str(c.polydispersity) + ": need 0 <= p < 1");
  }
  if (!(c.density > 0)) refuse("density = " + str(c.density) + " kg/m^2: need > 0");
  if (!(c.area_fraction > 0 && c.area_fraction <= 0.9)) {
    refuse("area_fraction = " + str(c.area_fraction) + ": need 0 < Phi <= 0.9");
  }
  if (!(c.intruder_diameter > 0)) {
    refuse("intruder_diameter = " + str(c.intruder_diameter) + " m: need > 0");
  }
  const double speed = std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
  if (!(speed > 0)) refuse("intruder velocity is zero: the run length is set by its travel");
  if (!(c.travel > 0) || !(c.steady_travel >= 0)) {
    refuse("travel = " + str(c.travel) + " d, steady_travel = " + str(c.steady_travel) +
           " d: need travel > 0 and steady_travel >= 0");
  }
  if (c.sample_every < 1) refuse("sample_every = " + str(c.sample_every) + ": need >= 1");
  if (c.field_every < 1) refuse("field_every = " + str(c.field_every) + ": need >= 1");
  if (c.threads < 1) refuse("threads = " + str(c.threads) + ": need >= 1");
  if (!(c.spin_ramp_time >= 0))
    refuse("spin_ramp_time = " + str(c.spin_ramp_time) + " s: need >= 0");
  if (!(c.max_overlap_fraction > 0)) {
    refuse("max_overlap_fraction = " + str(c.max_overlap_fraction) + ": need > 0");
  }
  if (!(c.relax_ke_per_grain > 0)) {
    refuse("relax_ke_per_grain = " + str(c.relax_ke_per_grain) + " J: need > 0");
  }
  if (!(c.lid_pressure >= 0) || !std::isfinite(c.lid_pressure) || !(c.lid_mass >= 0) ||
      !(c.lid_damping >= 0)) {
    refuse("lid_pressure = " + str(c.lid_pressure) + " N/m, lid_mass = " + str(c.lid_mass) +
           " kg, lid_damping = " + str(c.lid_damping) + " kg/s: need all >= 0 and finite");
  }
  if (c.lid_pressure > 0 && (!c.wall_top || c.periodic_y)) {
    refuse("lid_pressure = " + str(c.lid_pressure) +
           " N/m needs a top wall (the lid) and a box that is not periodic in y");
  }
  if (c.fields.enabled && (!(c.fields.spacing > 0) || c.fields.nx < 1 || c.fields.ny < 1)) {
    refuse("field grid: spacing = " + str(c.fields.spacing) + " m, nx = " + str(c.fields.nx) +
           ", ny = " + str(c.fields.ny) + ": need spacing > 0 and nx, ny >= 1");
  }
  const double d = c.grain_diameter;
  if (c.periodic_x && c.xmax - c.xmin < 3 * (d + c.intruder_diameter)) {
    refuse("periodic box length " + str(c.xmax - c.xmin) + " m is below 3 (d + D) = " +
           str(3 * (d + c.intruder_diameter)) + " m");
  }
  if (c.periodic_y && c.ymax - c.ymin < 3 * (d + c.intruder_diameter)) {
    refuse("periodic box height " + str(c.ymax - c.ymin) + " m is below 3 (d + D) = " +
           str(3 * (d + c.intruder_diameter)) + " m");
  }
  const LawCoefficients law = LawCoefficients::from(c.contact);
  if (!(c.dt > 0)) refuse("dt = " + str(c.dt) + " s: need > 0");
  const double v = impact_speed(c);
  const double m = c.density * kPi * 0.25 * d * d;
  const double tc = hertz_collision_time(law, 0.5 * d, 0.5 * d, m, m, v);
  if (!(c.max_dt_fraction > 0))
    refuse("max_dt_fraction = " + str(c.max_dt_fraction) + ": need > 0");
  if (c.dt > c.max_dt_fraction * tc) {
    refuse("dt = " + str(c.dt) + " s exceeds " + str(c.max_dt_fraction) +
           " of the binary collision time " + str(tc) + " s (two grains of d = " + str(d) +
           " m meeting at " + str(v) + " m/s); use dt <= " + str(c.max_dt_fraction * tc) + " s");
  }
  return tc;
}

long long travel_steps(const DemConfig& c) {
  const double speed = std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
  return static_cast<long long>(std::ceil(c.travel * c.grain_diameter / (speed * c.dt) - 1e-9));
}

DemConfig packing_config(const DemConfig& cfg) {
  DemConfig packing = cfg;
  packing.dt = std::min(cfg.dt, 0.1 * validate_config(cfg));
  return packing;
}

DemOutput run_simulation(const DemConfig& c, const ProgressCallback& progress) {
  return run_simulation(c, progress, {});
}

DemOutput run_simulation(const DemConfig& c, const ProgressCallback& progress,
                         const RunMonitor& monitor) {
  return run_simulation(c, progress, monitor, {});
}

namespace {

/// Refuses a prepared bed whose overlap at rest @p ov0 (fraction of a grain diameter) leaves
/// no room for the intruder's load; records it in @p out.
void check_bed_at_rest(const DemConfig& c, double ov0, DemOutput& out) {
  out.bed_max_overlap = ov0;
  // Without gravity a bed at rest overlaps only if it is compressed beyond jamming (for these
  // disks the overlap at rest is ~1e-4 d up to Phi ~0.84, then 1.6% at 0.86, 4.2% at 0.88,
  // 6.2% at 0.9: docs/stability.md). Above half the allowed overlap, the intruder's load
  // would stop the run on an overlap within a few thousand steps: refuse it now.
  const bool weightless = c.gravity[0] == 0.0 && c.gravity[1] == 0.0;
  if (weightless && ov0 > 0.5 * c.max_overlap_fraction) {
    refuse("the prepared bed (area fraction " + str(out.achieved_area_fraction) +
           ") is compressed beyond jamming: at rest it already overlaps by " + str(ov0) +
           " of a grain diameter, more than half of max_overlap_fraction = " +
           str(c.max_overlap_fraction) + ", which leaves no room for the intruder's load; "
           "lower grains.area_fraction (these disks jam near 0.84; 0.88 still runs, 0.9 does "
           "not)");
  }
  if (ov0 > c.max_overlap_fraction) {
    refuse("the prepared bed already overlaps by " + str(ov0) +
           " of a grain diameter at rest, above max_overlap_fraction = " +
           str(c.max_overlap_fraction) + ": the contacts are too soft for the load (gravity (" +
           str(c.gravity[0]) + ", " + str(c.gravity[1]) + ") m/s^2, density " + str(c.density) +
           " kg/m^2, grain diameter " + str(c.grain_diameter) +
           " m); stiffen the contact law or lower the load");
  }
}

/// The bed and the system of a run: a fresh bed (the packing cache or a preparation) or a
/// checkpoint's state, with the intruder, the options and the lid of @p c; the prepared bed's
/// overlap at rest checked before the first step. Fills the bed's entries of @p out.
std::unique_ptr<DemSystem> system_for_run(const DemConfig& c, const RunCheckpoint* resume,
                                          const ProgressCallback& progress, DemOutput& out) {
  std::unique_ptr<DemSystem> system;
  if (resume) {
    // the bed, the outputs so far and the system's state come from the checkpoint
    out = resume->out;
    out.resumed_from_step = resume->step;
    // the checkpoint holds no fingerprint: that of the same bed (the packing cache, or the
    // same preparation again)
    const PackedBed bed = prepare_packing(packing_config(c), progress);
    out.bed = bed_fingerprint(c, bed, make_wall_disks(c));
    system = std::make_unique<DemSystem>(system_options(c));
    system->set_bodies(resume->system.grains, resume->system.frozen);
  } else {
    // the bed is prepared at a step no larger than 0.1 of the collision time, whatever dt the
    // run tests (max_dt_fraction may allow more: stability studies); the same bed, and cache
    // entry, as before for every dt within the default limit
    const PackedBed bed = prepare_packing(packing_config(c), progress);
    out.packing_from_cache = bed.from_cache;
    out.packing_cache_note = bed.cache_note;
    out.achieved_area_fraction = bed.area_fraction;
    out.bed = bed_fingerprint(c, bed, make_wall_disks(c));
    system = system_on_bed(c, bed);
  }
  DemSystem& s = *system;
  s.set_intruder(c.intruder_position[0], c.intruder_position[1], 0.5 * c.intruder_diameter,
                 c.intruder_velocity[0], c.intruder_velocity[1], c.intruder_omega,
                 c.spin_ramp_time);
  s.set_store_pair_forces(c.fields.enabled);  // only the contact stress (and the lid) read them
  s.set_frictionless_path(c.frictionless_path);  // the run keeps its mu: no spring is ever read
  out.frictionless_path = s.frictionless_path_active();
  s.set_sleep(c.sleep_speed);
  if (c.lid_pressure > 0) {
    s.attach_lid(PressureLid(c, s));
    out.lid_mass = s.lid()->mass();
    out.lid_damping = s.lid()->damping();
  }
  if (resume) {
    s.restore(resume->system);
  } else {
    s.prepare();
    check_bed_at_rest(c, s.current_max_overlap_fraction(), out);
  }
  out.grains = s.grains();
  out.wall_grains = s.frozen();
  return system;
}

/// The bounds a sample is checked against (check_sample).
struct RunLimits {
  double speed = 0;        ///< m/s, the intruder's
  double speed_scale = 0;  ///< m/s, the fastest speed the scene imposes
  double energy = 0;       ///< J, the kinetic energy above which the run has blown up
};

/// Energy growth (a numerical instability): the grains' kinetic energy above that of all of
/// them moving at 3x the fastest speed the scene imposes (the intruder's surface, free fall
/// over the box height), plus all the work a lid could do in closing the box.
RunLimits run_limits(const DemConfig& c, const DemSystem& s) {
  RunLimits l;
  l.speed = std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
  const double grain_mass = s.grain_mass();
  l.speed_scale =
      std::max(l.speed + std::abs(c.intruder_omega) * 0.5 * c.intruder_diameter,
               std::sqrt(2.0 * std::hypot(c.gravity[0], c.gravity[1]) * (c.ymax - c.ymin)));
  l.energy = 0.5 * grain_mass * 9.0 * l.speed_scale * l.speed_scale +
             c.lid_pressure * (c.xmax - c.xmin) * (c.ymax - c.ymin);
  return l;
}

/// The intruder's sample at step @p k, after the checks that end a run that has gone wrong: a
/// non-finite state, energy growth, an overlap above the limit (RunFailure naming the grain).
/// The overlap raises @p largest_overlap.
IntruderSample checked_sample(DemSystem& s, const DemConfig& c, long long k,
                              const RunLimits& limits, double& largest_overlap) {
  const double t = s.time();
  IntruderSample smp;
  smp.time = t;
  smp.fx = s.intruder_fx();
  smp.fy = s.intruder_fy();
  smp.torque = s.intruder_torque();
  smp.contacts = s.intruder_touching();
  const double ke = s.kinetic_energy();
  const auto when = [&] { return "step " + str(k) + " (t = " + str(t) + " s): "; };
  if (!std::isfinite(smp.fx) || !std::isfinite(smp.fy) || !std::isfinite(smp.torque) ||
      !std::isfinite(ke)) {
    const int g = s.first_non_finite_grain();
    throw RunFailure(when() + "NaN: non-finite state (intruder force (" + str(smp.fx) + ", " +
                     str(smp.fy) + ") N, kinetic energy " + str(ke) + " J" +
                     (g >= 0 ? ", first at grain " + str(g) + describe_grain(s, g) : "") +
                     "); dt = " + str(c.dt) + " s may be too large");
  }
  if (ke > limits.energy) {
    const int g = s.fastest_grain();
    throw RunFailure(when() + "energy growth: the grains' kinetic energy " + str(ke) +
                     " J exceeds " + str(limits.energy) + " J (all of them at 3x the fastest "
                     "speed the scene imposes, " + str(limits.speed_scale) + " m/s, plus the "
                     "lid's work over the box); fastest grain " +
                     str(g) + describe_grain(s, g) + "; reduce dt (" + str(c.dt) + " s)");
  }
  const double ov = s.take_max_overlap_fraction();
  largest_overlap = std::max(largest_overlap, ov);
  if (ov > c.max_overlap_fraction) {
    const DemSystem::WorstOverlap w = s.worst_overlap();
    const std::string partner = w.j < 0 ? std::string("the intruder")
                                : w.j >= s.grains() ? "wall disk " + str(w.j - s.grains())
                                                    : "grain " + str(w.j);
    throw RunFailure(when() + "overlap: an overlap reached " + str(ov) +
                     " of a grain diameter, above max_overlap_fraction = " +
                     str(c.max_overlap_fraction) + " (now the largest: grain " + str(w.i) +
                     describe_grain(s, w.i) + " and " + partner + ", " + str(w.fraction) +
                     "); reduce dt (" + str(c.dt) + " s) or the intruder speed (" +
                     str(limits.speed) + " m/s), or stiffen the contact law");
  }
  return smp;
}

/// The grains touching the intruder now, as contacts of sample @p index (angle, normal force
/// compressive positive, tangential force on the intruder counter-clockwise positive, slip
/// velocity of the intruder's surface against the grain's contact point counter-clockwise
/// positive).
void record_contacts(const DemSystem& s, std::size_t index, DemOutput& out) {
  const IntruderContacts& ic = s.intruder_contacts();
  for (std::size_t q = 0; q < ic.grain.size(); ++q) {
    if (!ic.touching[q]) continue;
    IntruderContact con;
    con.sample = static_cast<std::int32_t>(index);
    double th = std::atan2(ic.ny[q], ic.nx[q]);
    if (th <= -kPi) th = kPi;
    con.theta = th;
    con.fn = ic.fn[q];   // the grain pushes the intruder inward: compressive positive
    con.ft = -ic.ft[q];  // force on the intruder, counter-clockwise positive
    con.vt = -ic.vt[q];  // the surface against the grain: the sign flip of ft
    con.slipping = ic.slipping[q] != 0;
    out.contacts.push_back(con);
  }
}

/// When checkpoints are due: every checkpoint_steps steps and every checkpoint_seconds of
/// wall time (RunControl), counted from the run's first step @p k0.
class CheckpointClock {
 public:
  CheckpointClock(const RunControl& control, long long k0)
      : control_(control), wall0_(std::chrono::steady_clock::now()) {
    next_step_ = control.checkpoint_steps > 0
                     ? (k0 / control.checkpoint_steps + 1) * control.checkpoint_steps
                     : -1;
    next_time_ = control.checkpoint_seconds > 0 ? control.checkpoint_seconds : -1;
  }
  /// Whether one is due at step @p k (and the next one scheduled).
  bool due(long long k) {
    bool due = false;
    if (next_step_ >= 0 && k >= next_step_) {
      due = true;
      next_step_ = (k / control_.checkpoint_steps + 1) * control_.checkpoint_steps;
    }
    if (next_time_ >= 0 && seconds() >= next_time_) {
      due = true;
      next_time_ = seconds() + control_.checkpoint_seconds;
    }
    return due;
  }

 private:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
  }
  const RunControl& control_;
  std::chrono::steady_clock::time_point wall0_;
  long long next_step_ = -1;
  double next_time_ = -1;
};

/// The step a run starts from: 0, or a checkpoint's (its fields' sums restored; a checkpoint
/// of a run of another length refused).
long long first_step(const RunCheckpoint* resume, long long n_steps, FieldAccumulator& fields,
                     DemOutput& out) {
  if (!resume) {
    out.steady_start_index = static_cast<std::size_t>(-1);
    return 0;
  }
  if (resume->planned_steps != n_steps) {
    refuse("the checkpoint is of a run of " + str(resume->planned_steps) +
           " steps, this one has " + str(n_steps) + ": another travel, dt or intruder speed");
  }
  fields.restore(resume->fields);
  return resume->step;
}

/// The run's counters of the system into @p out at its end.
void finish_output(const DemSystem& s, long long n_steps, DemOutput& out) {
  if (out.steady_start_index == static_cast<std::size_t>(-1)) {
    out.steady_start_index = out.samples.size();
  }
  if (!out.stopped_early) out.steps = n_steps;
  out.planned_steps = n_steps;
  out.list_builds = s.list_builds();
  out.threads_used = s.threads_used();
  out.threads_allowed = s.threads_allowed();
  out.steps_on_team = s.steps_on_team();
  if (s.steps() > 0) {
    out.sleeping_fraction =
        s.sleeping_grain_steps() / (double(s.steps()) * std::max(1, s.grains()));
  }
  out.sleep_wakes = s.woken();
  out.sleep_wake_builds = s.wake_builds();
}

}  // namespace

DemOutput run_simulation(const DemConfig& c, const ProgressCallback& progress,
                         const RunMonitor& monitor, const RunControl& control) {
  DemOutput out;
  const RunCheckpoint* resume = control.resume;
  out.collision_time = validate_config(c);
  const double d = c.grain_diameter;
  const std::unique_ptr<DemSystem> system = system_for_run(c, resume, progress, out);
  DemSystem& s = *system;
  const PressureLid* lid = s.lid();
  // the far-field stress reads the per-pair forces, kept when fields or a lid need them
  const bool far_field = c.fields.enabled || lid;
  const FarFieldRegion region = FarFieldRegion::of(c);
  if (far_field) {
    out.far_field_exclusion = region.exclusion;
    out.far_field_half_height = region.half_height;
  }

  const long long n_steps = travel_steps(c);
  const RunLimits limits = run_limits(c, s);
  const double steady_time = c.steady_travel * d / limits.speed;
  const long long progress_every = std::max(1LL, n_steps / 100);
  const bool report = progress || monitor;
  out.samples.reserve(static_cast<std::size_t>(n_steps / c.sample_every + 1));
  FieldAccumulator fields(c.fields);
  const long long k0 = first_step(resume, n_steps, fields, out);
  CheckpointClock checkpoints(control, k0);
  auto take_checkpoint = [&](long long k) {
    RunCheckpoint ck;
    ck.step = k;
    ck.planned_steps = n_steps;
    ck.system = s.snapshot();
    ck.out = out;
    ck.fields = fields.sums();
    control.checkpoint(ck);
  };

  // advance() runs the steps between two events (sample, field snapshot, progress report)
  // in one go; the state is the same as after single steps (the lid moves inside every step).
  auto next_multiple = [](long long k, long long every) { return (k / every + 1) * every; };
  for (long long k = k0; k < n_steps;) {
    long long next = std::min(n_steps, next_multiple(k, c.sample_every));
    if (c.fields.enabled) next = std::min(next, next_multiple(k, c.field_every));
    if (report) next = std::min(next, next_multiple(k, progress_every));
    s.advance(next - k);
    k = next;
    const double t = s.time();
    if (k % c.sample_every == 0) {
      if (lid) out.lid.push_back({t, lid->state().y, lid->state().pressure});
      if (far_field) out.far_field.push_back(far_field_stress(s, c, region));
      const IntruderSample smp = checked_sample(s, c, k, limits, out.run_max_overlap);
      const std::size_t index = out.samples.size();
      out.samples.push_back(smp);
      if (out.steady_start_index == static_cast<std::size_t>(-1) &&
          t >= steady_time * (1 - 1e-12)) {
        out.steady_start_index = index;
      }
      if (index >= out.steady_start_index) record_contacts(s, index, out);
    }
    if (c.fields.enabled && k % c.field_every == 0 && t >= steady_time * (1 - 1e-12)) {
      fields.add_snapshot(s);
    }
    if (report && (k % progress_every == 0 || k == n_steps)) {
      const double fraction = static_cast<double>(k) / static_cast<double>(n_steps);
      bool stop = false;
      if (monitor) {
        stop = monitor(out, fraction);
      } else {
        progress(fraction, "run");
      }
      if (stop && k < n_steps) {
        out.stopped_early = true;
        out.steps = k;
        break;
      }
    }
    if (k < n_steps) {
      const bool interrupted = control.interrupted && control.interrupted();
      const bool due = checkpoints.due(k) || interrupted;
      if (due && control.checkpoint) take_checkpoint(k);
      if (interrupted) {
        out.interrupted = true;
        out.stopped_early = true;
        out.steps = k;
        break;
      }
    }
  }
  if (c.fields.enabled) out.fields = fields.finish();
  finish_output(s, n_steps, out);
  return out;
}

}  // namespace grainlift::dem
