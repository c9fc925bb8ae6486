// Glue between the case file / shared schema and the DEM engine. Conversion only: the physics
// is in dem/src, the post-processing (surface stress, block averages, drag/lift) in shared/.
#include "grainlift/dem/dem_solver.h"

#include <fmt/format.h>
#include <omp.h>
#include <pthread.h>
#include <sched.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <cstdlib>
#include <limits>
#include <exception>
#include <stdexcept>
#include <thread>

#include "grainlift/dem/system/checkpoint.h"
#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/dem/step/vector_kernels.h"
#include "grainlift/shared/case/case_geometry.h"
#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/interrupt.h"
#include "grainlift/shared/statistics/force_statistics.h"
#include "grainlift/shared/statistics/statistics.h"
#include "grainlift/shared/statistics/replica_pool.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/surface/surface_stress.h"
#include "dem_result_parts.h"

namespace grainlift::dem {
namespace {

/// The engine's law for the case's name (the loader accepts only these; anything else is a bug).
ContactLaw contact_law_of(const std::string& name) {
  if (name == "kumar2019") return ContactLaw::kumar2019;
  if (name == "guillard2014") return ContactLaw::guillard2014;
  throw std::logic_error("grains.contact.law = \"" + name + "\" passed the loader");
}


}  // namespace

DemConfig make_dem_config(const Case& c, int threads) {
  DemConfig d;
  d.xmin = c.domain.x_range[0];
  d.xmax = c.domain.x_range[1];
  d.ymin = c.domain.y_range[0];
  d.ymax = c.domain.y_range[1];
  d.periodic_x = c.domain.periodic[0];
  d.periodic_y = c.domain.periodic[1];
  d.wall_bottom = c.domain.wall_bottom;
  d.wall_top = c.domain.wall_top;
  d.wall_left = c.domain.wall_left;
  d.wall_right = c.domain.wall_right;
  d.lid_pressure = c.domain.lid_pressure;  // Pa in the 2D reading = N/m of the engine's forces
  d.lid_free_disks = c.domain.lid == "free_disks";
  d.gravity = c.scene.gravity;
  d.grain_diameter = c.grains.diameter;
  d.polydispersity = c.grains.polydispersity;
  d.density = c.grains.density;
  d.area_fraction = c.grains.area_fraction;
  auto& ct = d.contact;
  ct.law = contact_law_of(c.grains.contact.law);
  ct.kn = c.grains.contact.kn;
  ct.kt = c.grains.contact.kt;
  ct.gamma_n = c.grains.contact.gamma_n;
  ct.gamma_t = c.grains.contact.gamma_t;
  ct.youngs_modulus = c.grains.contact.youngs_modulus;
  ct.poisson_ratio = c.grains.contact.poisson_ratio;
  ct.restitution = c.grains.contact.restitution;
  ct.friction = c.grains.friction;
  ct.intruder_friction = c.intruder.friction;
  d.intruder_diameter = c.intruder.diameter;
  d.intruder_position = c.intruder.position;
  d.intruder_velocity = c.intruder.velocity;
  d.intruder_omega = c.intruder.omega;
  d.spin_ramp_time = c.intruder.spin_ramp_time;
  d.dt = c.dem.dt;
  d.max_dt_fraction = c.dem.max_dt_fraction;
  d.travel = c.dem.travel;
  d.steady_travel = c.dem.steady_travel;
  d.seed = c.dem.seed;
  d.sample_every = c.dem.sample_every;
  d.sort_every = c.dem.sort_every;
  d.field_every = c.dem.field_every;
  d.frictionless_path = c.dem.frictionless_path;
  d.sleep_speed =
      c.dem.sleep ? c.dem.sleep_speed * std::hypot(c.intruder.velocity[0], c.intruder.velocity[1])
                  : -1.0;
  d.threads = threads;
  d.relax_ke_per_grain = c.dem.relax_ke;
  d.preparation = c.dem.preparation == "wall_compression" ? Preparation::wall_compression
                                                          : Preparation::radius_growth;
  d.compression_speed = c.dem.compression_speed;
  d.compression_drag = c.dem.compression_drag;
  d.packing_cache_dir = cache_folder(c.dem.packing_cache, "packings");
  const FieldGridLayout grid = field_grid_layout(c);
  d.fields.enabled = grid.enabled;
  d.fields.x0 = grid.x0;
  d.fields.y0 = grid.y0;
  d.fields.spacing = grid.spacing;
  d.fields.nx = grid.nx;
  d.fields.ny = grid.ny;
  return d;
}

namespace {

/// Relative standard errors of the mean drag and lift of the steady samples so far (block
/// averages over the case's blocks, corrected for correlated blocks), NaN until there are
/// output.blocks blocks of at least kMinBlockSamples samples each.
struct RelativeErrors {
  double drag = std::numeric_limits<double>::quiet_NaN();
  double lift = std::numeric_limits<double>::quiet_NaN();
};
constexpr std::size_t kMinBlockSamples = 5;

RelativeErrors relative_errors(const Case& c, const DemOutput& o) {
  RelativeErrors e;
  const std::size_t first = o.steady_start_index;
  const std::size_t B = std::size_t(c.output.blocks);
  if (first >= o.samples.size() || o.samples.size() - first < B * kMinBlockSamples) return e;
  std::vector<double> drag, lift;
  drag.reserve(o.samples.size() - first);
  lift.reserve(o.samples.size() - first);
  for (std::size_t i = first; i < o.samples.size(); ++i) {
    const DragLift dl = project_drag_lift(o.samples[i].fx, o.samples[i].fy, c.intruder.velocity[0],
                                          c.intruder.velocity[1]);
    drag.push_back(dl.drag);
    lift.push_back(dl.lift);
  }
  const BlockMean d = block_mean(drag, B), l = block_mean(lift, B);
  e.drag = d.stderr_corrected / std::abs(d.mean);
  e.lift = l.stderr_corrected / std::abs(l.mean);
  return e;
}

std::string percent(double x) {
  return std::isfinite(x) ? fmt::format("{:.1f}%", 100 * x) : std::string("?");
}

/// Where a run's checkpoint lives: <out>/dem.checkpoint.
std::string checkpoint_path(const RunOptions& opt) { return opt.out_dir + "/dem.checkpoint"; }

/// The checkpoint of @p opt.out_dir, checked to belong to case @p c. @throws InputError.
RunCheckpoint read_checkpoint(const Case& c, const RunOptions& opt) {
  const std::string path = checkpoint_path(opt);
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    throw InputError(fmt::format("{}: no checkpoint to resume from (a run writes one every "
                                 "dem.checkpoint_minutes and when interrupted)", path));
  }
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)),
                                         std::istreambuf_iterator<char>());
  RunCheckpoint ck;
  try {
    ck = decode_checkpoint(bytes);
  } catch (const CheckpointError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  if (ck.case_tag != c.source.hash) {
    throw InputError(fmt::format(
        "{}: the checkpoint is of another case (hash {}; {} with these overrides is {}): resume "
        "with the same case file and --set options",
        path, ck.case_tag, c.source.path, c.source.hash));
  }
  return ck;
}

/// What a run adds to its result beyond the means: the bed and path flags, a resume or an
/// interruption, sleeping, the travel the
/// means come from against the intruder's own wake, and the target error reached or not.
void add_run_notes(const Case& c, const DemConfig& cfg, const DemOutput& out, double target,
                   ProgressReporter* progress, const std::string& tag, bool checkpoints,
                   RunResult& r) {
  r.diagnostics.counts["frictionless_path"] = out.frictionless_path ? 1 : 0;
  if (!out.packing_cache_note.empty()) {
    if (progress) progress->message("warning: " + out.packing_cache_note);
    r.meta.notes += "; " + out.packing_cache_note;
  }
  r.diagnostics.values["bed_max_overlap"] = out.bed_max_overlap;
  if (out.resumed_from_step >= 0) {
    r.diagnostics.counts["resumed_from_step"] = out.resumed_from_step;
    r.meta.notes += fmt::format("; resumed from a checkpoint at step {}", out.resumed_from_step);
  }
  if (out.interrupted) {
    r.meta.partial = true;
    r.diagnostics.counts["interrupted_at_step"] = out.steps;
    r.meta.notes += fmt::format(
        "; PARTIAL: interrupted at step {} of {} ({:.3g} of {:g} d of travel){}", out.steps,
        out.planned_steps, travel_run(c, out), c.dem.travel,
        checkpoints ? "; a checkpoint was written: grainlift run CASE --resume DIR goes on" : "");
  }
  if (cfg.sleep_speed >= 0) {
    r.diagnostics.values["sleeping_fraction"] = out.sleeping_fraction;
    r.diagnostics.counts["sleep_wakes"] = out.sleep_wakes;
    r.diagnostics.counts["sleep_wake_builds"] = out.sleep_wake_builds;
  }
  if (target > 0) {
    const RelativeErrors final_errors = relative_errors(c, out);
    const double travel = travel_run(c, out);
    Diagnostics& diag = r.diagnostics;
    diag.values["target_error"] = target;
    diag.values["drag_relative_error"] = final_errors.drag;
    diag.values["lift_relative_error"] = final_errors.lift;
    diag.values["travel_run"] = travel;
    diag.counts["target_error_reached"] = out.stopped_early && !out.interrupted ? 1 : 0;
    const std::string what = fmt::format(
        "{}relative errors drag {} lift {} (block averages corrected for correlation)", tag,
        percent(final_errors.drag), percent(final_errors.lift));
    if (out.stopped_early && !out.interrupted) {
      r.meta.notes += fmt::format("; target error {} reached after {:.4g} d of travel: {}",
                                  percent(target), travel, what);
    } else {
      const std::string warning =
          fmt::format("warning: target error {} not reached in dem.travel = {:g} d: {}",
                      percent(target), c.dem.travel, what);
      if (progress) progress->message(warning);
      r.meta.notes += "; " + warning;
    }
  }
}

/// One run of the case on the bed of @p cfg (its seed). @p target: the relative error that
/// ends it (0: off); @p progress: the reporter, or nullptr for a silent replica; @p tag: the
/// progress line's prefix of the error. @p opt: checkpoints in opt->out_dir, and resume from
/// there when opt->resume (nullptr: neither, a replica). Every run stops at the next event
/// when the process is interrupted (interrupt.h); its result is then marked partial.
RunResult run_one(const Case& c, const DemConfig& cfg, double target, ProgressReporter* progress,
                  const std::string& tag, const RunOptions* opt = nullptr) {
  // The current errors on the progress line; with a target, the run ends once both are at or
  // below it.
  const RunMonitor monitor = [&](const DemOutput& so_far, double fraction) {
    const RelativeErrors e = relative_errors(c, so_far);
    std::string status =
        fmt::format("{}error drag {} lift {}", tag, percent(e.drag), percent(e.lift));
    if (target > 0) status += fmt::format(" (target {})", percent(target));
    if (progress) progress->update(fraction, "run", status);
    return target > 0 && e.drag <= target && e.lift <= target;
  };
  RunControl control;
  control.interrupted = [] { return interrupt_signal() != 0; };
  std::optional<RunCheckpoint> resume;
  const bool checkpoints = opt && opt->writer;
  if (opt && opt->resume) {
    resume = read_checkpoint(c, *opt);
    control.resume = &*resume;
    if (progress) {
      progress->message(fmt::format("resuming from {} at step {} of {}", checkpoint_path(*opt),
                                    resume->step, resume->planned_steps));
    }
  }
  if (checkpoints) {
    control.checkpoint_seconds = 60.0 * c.dem.checkpoint_minutes;
    control.checkpoint_steps = c.dem.checkpoint_steps;
    control.checkpoint = [&](const RunCheckpoint& ck) {
      RunCheckpoint tagged = ck;
      tagged.case_tag = c.source.hash;
      const std::vector<unsigned char> bytes = encode_checkpoint(tagged);
      // A checkpoint that cannot be written (a full disk) costs only the time since the last
      // good one: the run goes on, warns, keeps that one and tries again at the next.
      try {
        make_directories(opt->out_dir);
        write_bytes_atomically(checkpoint_path(*opt), bytes.data(), bytes.size());
      } catch (const std::exception& e) {
        const std::string warning =
            fmt::format("warning: checkpoint not written, the run goes on: {}", e.what());
        if (progress) progress->message(warning);
        else fmt::print(stderr, "{}\n", warning);
      }
    };
  }
  DemOutput out;
  try {
    out = run_simulation(
        cfg,
        [&](double fraction, const char* phase) {
          if (progress) progress->update(fraction, phase);
        },
        monitor, control);
  } catch (const ConfigError& e) {
    throw InputError(fmt::format("{}: {}", c.source.path, e.what()));
  } catch (const RunFailure& e) {
    throw RunError(e.what());
  }
  if (checkpoints && !out.interrupted) {
    std::error_code ignored;  // the run is complete: its checkpoint is of no more use
    std::filesystem::remove(checkpoint_path(*opt), ignored);
  }
  RunResult r = dem_result(c, out);
  r.diagnostics.texts["simd"] = simd_target();  // the step's loops: scalar, avx2, avx512, ...
  add_run_notes(c, cfg, out, target, progress, tag, checkpoints, r);
  return r;
}

/// With OpenMP thread binding on (OMP_PROC_BIND), the main thread is bound to one place and
/// a std::thread inherits that binding: all replicas would share one core. The processors of
/// each place (asked on the main thread, where OpenMP's settings apply), to bind replica k to
/// place k mod (number of places); empty without binding (the scheduler places them). The
/// engine opens no OpenMP region on one thread, which would bind the worker to the first place.
std::vector<cpu_set_t> replica_places() {
  std::vector<cpu_set_t> places;
  if (omp_get_proc_bind() == omp_proc_bind_false) return places;
  for (int p = 0; p < omp_get_num_places(); ++p) {
    std::vector<int> ids(static_cast<std::size_t>(omp_get_place_num_procs(p)));
    omp_get_place_proc_ids(p, ids.data());
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int id : ids) CPU_SET(id, &set);
    places.push_back(set);
  }
  return places;
}

/// --replicas N: N runs side by side, seeds dem.seed + k (one bed each), the threads shared
/// out (at least one each), pooled (pool_replicas). With dem.target_error each replica stops
/// at target sqrt(N), so that the pooled error is about the target.
RunResult run_replicas(const Case& c, const RunOptions& opt, ProgressReporter& progress) {
  const int n = opt.replicas;
  const int threads = std::max(1, opt.threads / n);
  const double target = c.dem.target_error * std::sqrt(double(n));
  std::vector<RunResult> results(static_cast<std::size_t>(n));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  std::vector<std::thread> workers;
  const std::vector<cpu_set_t> places = replica_places();
  for (int k = 0; k < n; ++k) {
    workers.emplace_back([&, k] {
      if (!places.empty()) {
        const cpu_set_t& set = places[static_cast<std::size_t>(k) % places.size()];
        pthread_setaffinity_np(pthread_self(), sizeof set, &set);
      }
      try {
        DemConfig cfg = make_dem_config(c, threads);
        cfg.seed = c.dem.seed + std::uint64_t(k);
        // replica 0 reports for all (they run the same length)
        results[std::size_t(k)] = run_one(c, cfg, target, k == 0 ? &progress : nullptr,
                                          fmt::format("replica 1/{}: ", n));
      } catch (...) {
        errors[std::size_t(k)] = std::current_exception();
      }
    });
  }
  for (auto& w : workers) w.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  RunResult pooled = pool_replicas(results);
  pooled.meta.notes += fmt::format(
      "; pooled over {} replicas (seeds {} to {}, {} thread(s) each): means and errors from "
      "the spread between replicas; force series, lid and far field of the first",
      n, c.dem.seed, c.dem.seed + std::uint64_t(n - 1), threads);
  std::vector<double> seeds;
  for (int k = 0; k < n; ++k) seeds.push_back(double(c.dem.seed + std::uint64_t(k)));
  pooled.diagnostics.series["replica_seed"] = seeds;
  return pooled;
}

}  // namespace

SolverEntry solver_entry() {
  SolverEntry e;
  e.name = "dem";
  e.description = "discrete element method, 2D frictional disks (Kumar 2019 contact law)";
  e.run = [](const Case& c, const RunOptions& opt, ProgressReporter& progress) {
    // a SIMD target asked for and not available: the run's bits would not be those asked for
    if (const std::string why = simd_setting_error(); !why.empty()) throw RunError(why);
    if (opt.replicas > 1) {
      if (opt.resume) {
        throw InputError("--resume continues a single run: --replicas > 1 writes no checkpoints");
      }
      return run_replicas(c, opt, progress);
    }
    return run_one(c, make_dem_config(c, opt.threads), c.dem.target_error, &progress, "", &opt);
  };
  return e;
}

}  // namespace grainlift::dem
