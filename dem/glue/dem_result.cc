// The DEM's result in the shared schema (dem_result): from the engine's DemOutput the forces
// and their block means, the surface stresses with their errors, the fields, the lid, the far
// field, the bed's fingerprint, the geometry and /diagnostics. LAMMPS imports use it too.
#include "grainlift/dem/dem_solver.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/shared/case/case_geometry.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/statistics/force_statistics.h"
#include "grainlift/shared/statistics/statistics.h"
#include "grainlift/shared/surface/surface_stress.h"
#include "dem_result_parts.h"

namespace grainlift::dem {

/// The travel the run reached, in grain diameters (dem.travel when it ran all its steps).
double travel_run(const Case& c, const DemOutput& out) {
  return out.planned_steps > 0 ? c.dem.travel * double(out.steps) / double(out.planned_steps)
                               : 0.0;
}

namespace {

/// Block mean of the samples after the steady-state start, and its correlation-corrected
/// standard error (the one rule of statistics.h) where the blocks give one (left unset for no
/// samples).
void steady_mean(const std::vector<double>& steady, int blocks, double& mean,
                 std::optional<double>& stderr_) {
  if (steady.empty()) return;
  const BlockMean b = block_mean(steady, std::size_t(blocks));
  mean = b.mean;
  if (std::isfinite(b.stderr_corrected)) stderr_ = b.stderr_corrected;
}

/// The per-angle standard errors of the surface stresses: the profile of each block of the
/// averaged samples (the blocks of block_mean: B blocks of n / B samples, the first n mod B
/// samples left out), then block_mean over the B values at each angle.
void add_surface_stderr(const Case& c, const DemOutput& out, double heading,
                        SurfaceDistribution& s) {
  const std::size_t n = out.samples.size() - out.steady_start_index;
  const std::size_t B = std::min<std::size_t>(std::size_t(c.output.blocks), n);
  if (B < 2) return;
  const std::size_t len = n / B, first = out.steady_start_index + (n - len * B);
  std::vector<SurfaceStressEstimator> blocks(
      B, SurfaceStressEstimator(c.output.angles, c.output.kernel_width_deg, c.intruder.diameter));
  std::size_t k = 0;
  while (k < out.contacts.size() && std::size_t(out.contacts[k].sample) < first) ++k;
  for (std::size_t i = first; i < out.samples.size(); ++i) {
    SurfaceStressEstimator& e = blocks[(i - first) / len];
    for (; k < out.contacts.size() && std::size_t(out.contacts[k].sample) == i; ++k) {
      const auto& ct = out.contacts[k];
      e.add(wrap_angle(ct.theta - heading), ct.fn, ct.ft);
    }
    e.end_frame();
  }
  std::vector<SurfaceDistribution> profiles;
  for (const auto& e : blocks) profiles.push_back(e.result());
  const std::size_t M = s.theta.size();
  std::vector<double> se_n(M), se_t(M), values(B);
  for (std::size_t m = 0; m < M; ++m) {
    for (std::size_t b = 0; b < B; ++b) values[b] = profiles[b].sigma_n[m];
    se_n[m] = block_mean(values, B).stderr_corrected;
    for (std::size_t b = 0; b < B; ++b) values[b] = profiles[b].sigma_t[m];
    se_t[m] = block_mean(values, B).stderr_corrected;
  }
  s.sigma_n_stderr = std::move(se_n);
  s.sigma_t_stderr = std::move(se_t);
}


/// /forces, and from the averaged samples /means (block averages) and /surface, /histogram.
void add_forces_means_and_surface(const Case& c, const DemOutput& out, RunResult& r) {
  const double vx = c.intruder.velocity[0], vy = c.intruder.velocity[1];
  const double heading = std::atan2(vy, vx);

  // Force series (all samples, including the transient).
  ForceSeries f;
  std::vector<double> drag, lift, torque, contacts;
  for (std::size_t i = 0; i < out.samples.size(); ++i) {
    const auto& s = out.samples[i];
    f.time.push_back(s.time);
    f.fx.push_back(s.fx);
    f.fy.push_back(s.fy);
    f.torque.push_back(s.torque);
    f.contacts.push_back(s.contacts);
    if (i >= out.steady_start_index) {
      const DragLift dl = project_drag_lift(s.fx, s.fy, vx, vy);
      drag.push_back(dl.drag);
      lift.push_back(dl.lift);
      torque.push_back(s.torque);
      contacts.push_back(s.contacts);
    }
  }
  r.forces = std::move(f);
  if (!drag.empty()) {
    const std::size_t B = std::size_t(c.output.blocks);
    const BlockMean d = block_mean(drag, B), l = block_mean(lift, B), t = block_mean(torque, B),
                    n = block_mean(contacts, B);
    MeanForces m;
    m.drag = d.mean;
    m.lift = l.mean;
    m.torque = t.mean;
    auto se = [](const BlockMean& b) {
      return std::isfinite(b.stderr_corrected) ? std::optional<double>(b.stderr_corrected)
                                             : std::nullopt;
    };
    m.drag_stderr = se(d);
    m.lift_stderr = se(l);
    m.torque_stderr = se(t);
    m.contacts = n.mean;
    m.samples = std::int64_t(d.samples);
    m.blocks = std::int64_t(d.blocks);
    r.means = m;

    // Surface distributions from the intruder contacts of every averaged sample.
    SurfaceStressEstimator kernel(c.output.angles, c.output.kernel_width_deg,
                                  c.intruder.diameter);
    ContactHistogram hist(c.output.histogram_bins);
    std::size_t k = 0;
    for (std::size_t i = out.steady_start_index; i < out.samples.size(); ++i) {
      for (; k < out.contacts.size() && std::size_t(out.contacts[k].sample) == i; ++k) {
        const auto& ct = out.contacts[k];
        const double theta = wrap_angle(ct.theta - heading);
        kernel.add(theta, ct.fn, ct.ft);
        hist.add(theta, ct.fn, ct.ft, ct.slipping, ct.vt);
      }
      kernel.end_frame();
      hist.end_frame();
    }
    r.surface = kernel.result();
    r.histogram = hist.result();
    add_surface_stderr(c, out, heading, *r.surface);
  }
}

/// /fields: the accumulated grid (velocity and temperature NaN where no grain ever was).
void add_fields(const Case& c, const DemOutput& out, RunResult& r) {
  if (out.fields.nx > 0 && out.fields.snapshots > 0) {
    const auto& a = out.fields;
    FieldGrid g;
    const FieldGridLayout layout = field_grid_layout(c);
    g.x = layout.x_centres();
    g.y = layout.y_centres();
    // Velocity and temperature are undefined in bins no grain ever covered (the wake cavity,
    // the intruder): NaN there, not zero.
    auto where_grains = [&](std::vector<double> v) {
      for (std::size_t i = 0; i < v.size(); ++i)
        if (!(a.area_fraction[i] > 0)) v[i] = std::numeric_limits<double>::quiet_NaN();
      return v;
    };
    g.velocity_x = where_grains(a.vx);
    g.velocity_y = where_grains(a.vy);
    g.area_fraction = a.area_fraction;
    g.granular_temperature = where_grains(a.granular_temperature);
    g.stress_xx = a.sxx;
    g.stress_xy = a.sxy;
    g.stress_yy = a.syy;
    std::vector<double> p(a.sxx.size());
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = -0.5 * (a.sxx[i] + a.syy[i]);
    g.pressure = std::move(p);
    r.fields = std::move(g);
  }
}

/// /lid: the lid's series and its mean pressure after the steady start.
void add_lid(const Case& c, const DemOutput& out, RunResult& r) {
  if (!out.lid.empty()) {
    LidSeries l;
    std::vector<double> steady;
    for (std::size_t i = 0; i < out.lid.size(); ++i) {
      l.time.push_back(out.lid[i].time);
      l.y.push_back(out.lid[i].y);
      l.pressure.push_back(out.lid[i].pressure);
      if (i >= out.steady_start_index) steady.push_back(out.lid[i].pressure);
    }
    l.target = c.domain.lid_pressure;
    l.mass = out.lid_mass;
    l.damping = out.lid_damping;
    steady_mean(steady, c.output.blocks, l.mean, l.mean_stderr);
    r.lid = std::move(l);
  }
}

/// /far_field: the stress the bed carries away from the intruder, and its steady mean.
void add_far_field(const Case& c, const DemOutput& out, RunResult& r) {
  if (!out.far_field.empty()) {
    FarFieldSeries ff;
    std::vector<double> steady;
    for (std::size_t i = 0; i < out.far_field.size(); ++i) {
      const FarFieldSample& s = out.far_field[i];
      ff.time.push_back(s.time);
      ff.pressure.push_back(s.pressure);
      ff.stress_xx.push_back(s.sxx);
      ff.stress_xy.push_back(s.sxy);
      ff.stress_yy.push_back(s.syy);
      if (i >= out.steady_start_index && std::isfinite(s.pressure)) steady.push_back(s.pressure);
    }
    ff.exclusion = out.far_field_exclusion;
    ff.half_height = out.far_field_half_height;
    steady_mean(steady, c.output.blocks, ff.mean, ff.mean_stderr);
    r.far_field = std::move(ff);
  }
}

/// /bed: the prepared bed's fingerprint.
void add_bed(const DemOutput& out, RunResult& r) {
  if (!out.bed.gap_fraction.empty()) {
    const BedFingerprint& f = out.bed;
    BedStructure b;
    b.contacts_per_grain = f.contacts_per_grain;
    b.rattler_fraction = f.rattler_fraction;
    b.fabric_xx = f.fabric_xx;
    b.fabric_xy = f.fabric_xy;
    b.fabric_yy = f.fabric_yy;
    b.mean_gap = f.mean_gap;
    b.gap_edges = f.gap_edges;
    b.gap_fraction = f.gap_fraction;
    b.band_y = f.band_y;
    b.band_area_fraction = f.band_area_fraction;
    b.ring_r = f.ring_r;
    b.ring_area_fraction = f.ring_area_fraction;
    r.bed = std::move(b);
  }
}

/// /geometry (with the pressure scale), the notes and /diagnostics.
void add_geometry_notes_and_diagnostics(const Case& c, const DemOutput& out, RunResult& r) {
  r.geometry = case_geometry(c);
  Geometry& q = r.geometry;
  // Pressure scale: the lid pressure plus the lithostatic pressure at the intruder (either may
  // be 0); without either, the pressure the bed carries away from the intruder (/far_field),
  // else the mean drag per unit projected area D / diameter (a dynamic pressure).
  const double stated = c.stated_pressure();
  const bool measured = stated == 0 && r.far_field && r.far_field->mean > 0;
  std::string source = c.domain.lid_pressure > 0 ? "lid + lithostatic" : "lithostatic";
  if (stated > 0) {
    q.pressure_scale = stated;
  } else if (measured) {
    q.pressure_scale = r.far_field->mean;
    source = "far field";
  } else {
    q.pressure_scale = r.means ? std::abs(r.means->drag) / c.intruder.diameter : 0.0;
    source = "drag / D";
  }
  r.meta.notes = fmt::format(
      "grains {} (walls {}), area fraction {:.4f}, packing {}, collision time {:.3g} s, "
      "steps {}, pressure_scale from {}",
      out.grains, out.wall_grains, out.achieved_area_fraction,
      out.packing_from_cache ? "reused from cache" : "prepared", out.collision_time, out.steps,
      source);
  Diagnostics& diag = r.diagnostics;
  diag.counts = {{"grains", out.grains},
                 {"wall_grains", out.wall_grains},
                 {"steps", out.steps},
                 {"list_builds", out.list_builds},
                 {"threads_used", out.threads_used},
                 {"threads_allowed", out.threads_allowed},
                 {"steps_on_team", out.steps_on_team},
                 {"packing_from_cache", out.packing_from_cache ? 1 : 0},
                 {"samples", static_cast<long long>(out.samples.size())},
                 {"steady_start_sample", static_cast<long long>(out.steady_start_index)}};
  diag.values = {{"area_fraction", out.achieved_area_fraction},
                 {"collision_time", out.collision_time}};
  diag.texts = {{"pressure_scale_source", source}};
  // the travel the means come from, and whether the intruder had met its own wake by then
  // (its front reaching bed it disturbed across the periodic boundary): the continuum's
  // "periodic" far field stands for means after it, "open" for means before it
  diag.values["mean_travel_from"] = c.dem.steady_travel;
  diag.values["mean_travel_to"] = travel_run(c, out);
  const double wake = solver_box(c).wake_travel / c.grains.diameter;
  if (std::isfinite(wake)) {
    diag.values["wake_travel"] = wake;
    diag.counts["crossed_own_wake"] = travel_run(c, out) > wake ? 1 : 0;
  }
  if (r.lid && !r.lid->y.empty()) {
    diag.values["lid_height_start"] = r.lid->y.front();
    diag.values["lid_height_end"] = r.lid->y.back();
  }
  if (r.lid) {
    r.meta.notes += fmt::format(
        "; lid: target {:.6g} Pa, mean {:.6g} +- {:.2g} Pa after the steady start, lid height "
        "{:.6g} -> {:.6g} m, mass {:.3g} kg, damping {:.3g} kg/s",
        r.lid->target, r.lid->mean, r.lid->mean_stderr.value_or(0.0),
        r.lid->y.empty() ? 0.0 : r.lid->y.front(), r.lid->y.empty() ? 0.0 : r.lid->y.back(),
        r.lid->mass, r.lid->damping);
  }
}
}  // namespace

RunResult dem_result(const Case& c, const DemOutput& out) {
  RunResult r;
  add_forces_means_and_surface(c, out, r);
  add_fields(c, out, r);
  add_lid(c, out, r);
  add_far_field(c, out, r);
  add_bed(out, r);
  add_geometry_notes_and_diagnostics(c, out, r);
  return r;
}

}  // namespace grainlift::dem
