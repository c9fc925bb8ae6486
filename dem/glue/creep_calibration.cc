// `grainlift calibrate --nonlocal` (calibration.h): the creeping-layer cell on the case's grains,
// one bed per seed, and the cooperativity amplitude A fitted on each bed and pooled.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include "grainlift/dem/calibration.h"
#include "grainlift/dem/errors.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/side_by_side.h"
#include "grainlift/shared/statistics/statistics.h"

namespace grainlift::dem {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The profile of one bed (y from the bottom wall's centre line, the walls' layers not fitted).
CreepProfile profile_of(const ShearCellResult& r, double d, double wall_layer) {
  CreepProfile p;
  p.y = r.profile_y;
  p.vx = r.profile_vx;
  p.vx_err = r.profile_vx_stderr;
  p.pressure = r.profile_pressure;
  p.dv = r.profile_dv;
  p.dv_err = r.profile_dv_stderr;
  p.psi6 = r.profile_psi6;
  p.shear_stress = r.shear_stress.mean;
  p.shear_stress_err = r.shear_stress.se;
  p.bottom = 0;
  p.top = r.lid_height.mean;
  p.y_min = wall_layer * d;
  p.y_max = p.top - wall_layer * d;
  return p;
}

/// The beds' profiles pooled bin by bin (statistics.h's pooled_mean for the velocities and tau,
/// plain means for the pressure and the lid's height), over the bins all have; the bins within
/// @p wall_margin (m) of a wall are not fitted.
CreepProfile pooled_profile(const std::vector<CreepProfile>& beds, double wall_margin) {
  std::size_t bins = beds.front().y.size();
  for (const CreepProfile& b : beds) bins = std::min(bins, b.y.size());
  const auto pool = [&](auto value, auto error) {
    std::vector<double> m, e;
    for (const CreepProfile& b : beds) m.push_back(value(b)), e.push_back(error(b));
    return pooled_mean(m, e);
  };
  const auto mean = [&](auto value) {
    double s = 0;
    for (const CreepProfile& b : beds) s += value(b);
    return s / double(beds.size());
  };
  CreepProfile p = beds.front();
  for (auto* v : {&p.y, &p.vx, &p.vx_err, &p.pressure, &p.dv, &p.dv_err, &p.psi6})
    v->resize(bins, std::nan(""));
  for (std::size_t k = 0; k < bins; ++k) {
    const PooledMean v = pool([k](const CreepProfile& b) { return b.vx[k]; },
                              [k](const CreepProfile& b) { return b.vx_err[k]; });
    const PooledMean dv = pool([k](const CreepProfile& b) { return b.dv[k]; },
                               [k](const CreepProfile& b) { return b.dv_err[k]; });
    p.vx[k] = v.mean, p.vx_err[k] = v.error, p.dv[k] = dv.mean, p.dv_err[k] = dv.error;
    p.pressure[k] = mean([k](const CreepProfile& b) { return b.pressure[k]; });
    double order = 0, beds_with = 0;  // the beds' last states, those measured
    for (const CreepProfile& b : beds)
      if (k < b.psi6.size() && std::isfinite(b.psi6[k])) order += b.psi6[k], beds_with += 1;
    p.psi6[k] = beds_with > 0 ? order / beds_with : std::nan("");
  }
  const PooledMean tau = pool([](const CreepProfile& b) { return b.shear_stress; },
                              [](const CreepProfile& b) { return b.shear_stress_err; });
  p.shear_stress = tau.mean;
  p.shear_stress_err = tau.error;
  p.top = mean([](const CreepProfile& b) { return b.top; });
  p.y_max = p.top - wall_margin;
  return p;
}

}  // namespace

CreepCalibration calibrate_cooperativity(const Case& c, const CreepOptions& o, const MuIFit& law,
                                         const std::function<void(const std::string&)>& say) {
  ShearCellConfig cell = case_shear_cell(c, o.pressure, o.threads, o.width, o.height);
  const double pressure = cell.pressure;
  const DemConfig& g = cell.grains;
  const double d = g.grain_diameter, gap = (o.height - 1) * d;
  CreepCalibration out;
  // the weight of the bed (at its prepared area fraction) that makes p(bottom) = ratio P
  cell.gravity = (o.bottom_pressure_ratio - 1) * pressure / (g.density * g.area_fraction * gap);
  cell.wall_speed = o.top_inertial_number * 10 * std::sqrt(pressure / g.density);
  const auto steps = [&](double travel) {
    return static_cast<long long>(std::ceil(travel * d / cell.wall_speed / g.dt));
  };
  cell.run_in_steps = steps(o.run_in_travel);
  cell.measure_steps = steps(o.window_travel);
  cell.max_run_in_steps = cell.run_in_steps + 2 * cell.measure_steps;
  cell.sample_every = static_cast<int>(std::max(10LL, cell.measure_steps / 4000));
  say(fmt::format("creeping-layer cell: {} d x {} d, P {} N/m on the lid, gravity {:.4g} m/s^2 "
                  "(p at the bottom ~ {} P), lid at {:.4g} m/s, {} + {} steps, {} seeds",
                  o.width, o.height, pressure, cell.gravity, o.bottom_pressure_ratio,
                  cell.wall_speed, cell.run_in_steps, cell.measure_steps, o.seeds));
  const FluidityMaterial material{law.mu_s, law.mu_2, law.I0, g.density, d};
  std::vector<CreepProfile> beds;
  std::vector<double> a, a_err;
  // The seeds' beds side by side, as many at once as there are threads (one thread each when
  // there are more seeds than threads), each reported in order with its own A as it ends.
  const std::size_t n = static_cast<std::size_t>(std::max(0, o.seeds));
  const int workers = std::max(1, std::min(o.threads, o.seeds));
  std::vector<ShearCellConfig> cells(n, cell);
  std::vector<double> seconds(n, 0.0);
  out.cells.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    cells[k].grains.seed = cell.grains.seed + static_cast<std::uint64_t>(k);
    cells[k].grains.threads = std::max(1, o.threads / workers);
  }
  auto run = [&](std::size_t k) {
    const auto t1 = std::chrono::steady_clock::now();
    try {
      out.cells[k] = run_shear_cell(cells[k]);
    } catch (const ConfigError& e) {
      throw InputError(fmt::format("{}: creeping-layer cell: {}", c.source.path, e.what()));
    } catch (const RunFailure& e) {
      throw RunError(fmt::format("{}: creeping-layer cell: {}", c.source.path, e.what()));
    }
    seconds[k] = seconds_since(t1);
  };
  auto report = [&](std::size_t k) {
    const ShearCellResult& r = out.cells[k];
    beds.push_back(profile_of(r, d, cell.wall_layer));
    // each bed's own A, with the profile's error only (mu_s's is common to all beds)
    const CooperativityFit f = fit_cooperativity(beds.back(), material, 0.0, o.fit);
    if (f.ok) a.push_back(f.amplitude), a_err.push_back(f.amplitude_err);
    say(fmt::format("seed {}: tau {:.4g} +- {:.2g} N/m, mu at the lid {:.4f}, {}steady; A {} "
                    "({:.1f} s)",
                    cells[k].grains.seed, r.shear_stress.mean, r.shear_stress.se,
                    r.friction.mean, r.steady ? "" : "NOT ",
                    f.ok ? fmt::format("{:.3f} +- {:.3f} (chi2/dof {:.2f}, C {:.2f})", f.amplitude,
                                       f.amplitude_err, f.chi2_per_dof, f.scale)
                         : "not determined: " + f.message,
                    seconds[k]));
  };
  side_by_side(n, workers, run, report);
  out.profile = pooled_profile(beds, cell.wall_layer * d);
  out.fit = fit_cooperativity(out.profile, material, law.mu_s_err, o.fit);
  out.profile_fit_amplitude = out.fit.amplitude;
  const auto curve = [&](double A) {
    std::vector<double> v = fluidity_velocity(out.profile, material, A, o.fit.xi_max);
    for (double& x : v) x = out.fit.floor + out.fit.scale * x;
    return v;
  };
  if (out.fit.amplitude > 0) out.fit_velocity = curve(out.fit.amplitude);
  out.local_velocity = curve(o.fit.a_min);
  if (out.fit.ok && a.size() == beds.size() && a.size() >= 2) {
    // A is the beds' pooled mean (the larger of their scatter and their own errors), with the
    // part of mu_s's error found on the pooled profile added
    const PooledMean m = pooled_mean(a, a_err);
    out.fit.amplitude = m.mean;
    out.fit.profile_err = m.error;
    out.fit.amplitude_err = std::hypot(m.error, out.fit.mu_s_err_part);
  }
  return out;
}

}  // namespace grainlift::dem
