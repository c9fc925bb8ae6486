// Simple-shear cell at imposed pressure (shear_cell.h): bed, lid at P moving at U, run-in
// extended until steady, measurement window with samples, velocity profile and block errors.
#include "grainlift/dem/scenes/shear_cell.h"
#include "grainlift/dem/scenes/bond_order.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/errors.h"
#include "scenes/message_number.h"
#include "grainlift/dem/boundaries/lid.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/system/system_setup.h"
#include "grainlift/shared/statistics/statistics.h"

namespace grainlift::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLidDampingFraction = 0.1;  // of PressureLid::default_damping (see below)

using detail::str;

[[noreturn]] void refuse(const std::string& what) { throw ConfigError("shear cell: " + what); }

void validate(const ShearCellConfig& c, const DemConfig& dc) {
  const double d = dc.grain_diameter;
  if (!(d > 0) || !(dc.density > 0)) refuse("grain_diameter and density must be > 0");
  if (!(c.width >= 3)) refuse("width = " + str(c.width) + " d: need >= 3 (the period in x)");
  if (!(c.height >= 2 * c.wall_layer + 5)) {
    refuse("height = " + str(c.height) + " d: need >= 2 wall_layer + 5 = " +
           str(2 * c.wall_layer + 5) + " d (a bulk of at least three bins)");
  }
  if (!(c.wall_layer >= 1)) refuse("wall_layer = " + str(c.wall_layer) + " d: need >= 1");
  if (!(c.pressure > 0) || !std::isfinite(c.pressure)) {
    refuse("pressure = " + str(c.pressure) + " N/m: need > 0 and finite");
  }
  if (!(c.gravity >= 0) || !std::isfinite(c.gravity)) {
    refuse("gravity = " + str(c.gravity) + " m/s^2: need >= 0 and finite (it points along -y)");
  }
  if (!(c.wall_speed >= 0) || !std::isfinite(c.wall_speed)) {
    refuse("wall_speed = " + str(c.wall_speed) + " m/s: need >= 0 and finite");
  }
  if (c.run_in_steps < 0 || c.measure_steps < 1 || c.max_run_in_steps < 0) {
    refuse("run_in_steps = " + str(c.run_in_steps) + ", measure_steps = " + str(c.measure_steps) +
           ", max_run_in_steps = " + str(c.max_run_in_steps) + ": need >= 0, >= 1, >= 0");
  }
  if (c.sample_every < 1) refuse("sample_every = " + str(c.sample_every) + ": need >= 1");
  if (c.blocks < 4 || c.blocks % 2 != 0 ||
      c.measure_steps / c.sample_every < static_cast<long long>(4 * c.blocks)) {
    refuse("blocks = " + str(c.blocks) + ", " + str(c.measure_steps / c.sample_every) +
           " samples per window: need an even number >= 4 of blocks of >= 4 samples");
  }
  if (!(c.steady_sigma > 0)) refuse("steady_sigma = " + str(c.steady_sigma) + ": need > 0");
  if (!(dc.dt > 0)) refuse("dt = " + str(dc.dt) + " s: need > 0");
  // dt against the binary collision time at the faster of U and the pressure's velocity
  // scale sqrt(P / rho_s) (the impact speeds of the cell)
  const double v = std::max(c.wall_speed, std::sqrt(c.pressure / dc.density));
  const double m = dc.density * kPi * 0.25 * d * d;
  const double tc =
      hertz_collision_time(LawCoefficients::from(dc.contact), 0.5 * d, 0.5 * d, m, m, v);
  if (dc.dt > dc.max_dt_fraction * tc) {
    refuse("dt = " + str(dc.dt) + " s exceeds " + str(dc.max_dt_fraction) +
           " of the binary collision time " + str(tc) + " s at " + str(v) + " m/s; use dt <= " +
           str(dc.max_dt_fraction * tc) + " s");
  }
}

/// x[begin, end) as a series of its own.
std::vector<double> window_of(const std::vector<double>& x, std::size_t begin, std::size_t end) {
  return std::vector<double>(x.begin() + std::ptrdiff_t(begin), x.begin() + std::ptrdiff_t(end));
}

/// The block mean of x[begin, end) with its correlation-corrected error (statistics.h).
MeanError block_stat(const std::vector<double>& x, std::size_t begin, std::size_t end,
                     int blocks) {
  const BlockMean m = block_mean(window_of(x, begin, end), std::size_t(blocks));
  return {m.mean, m.stderr_corrected};
}

/// Mean and error of the ratio num / den per block (both series over the same range, so the
/// same blocks), by the block rule of statistics.h applied to the B ratios.
MeanError block_ratio(const std::vector<double>& num, const std::vector<double>& den,
                      std::size_t begin, std::size_t end, int blocks) {
  const std::vector<double> a = block_means(window_of(num, begin, end), std::size_t(blocks));
  const std::vector<double> b = block_means(window_of(den, begin, end), std::size_t(blocks));
  std::vector<double> r(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) r[k] = a[k] / b[k];
  const std::size_t used = a.empty() ? 0 : (end - begin) / a.size() * a.size();
  const BlockMean m = block_mean_of(r, used);
  return {m.mean, m.stderr_corrected};
}

/// Whether the two halves of x[begin, end) in blocks agree within sigma combined errors.
bool halves_agree(const std::vector<double>& x, std::size_t begin, std::size_t end, int blocks,
                  double sigma, const std::vector<double>* den = nullptr) {
  const std::size_t mid = begin + (end - begin) / 2;
  const auto half = [&](std::size_t lo, std::size_t hi) {
    return den ? block_ratio(x, *den, lo, hi, blocks / 2) : block_stat(x, lo, hi, blocks / 2);
  };
  const MeanError a = half(begin, mid), b = half(mid, end);
  return std::abs(a.mean - b.mean) <= sigma * std::hypot(a.se, b.se);
}

/// Velocity profile over the window: bins of one d above the bottom wall's centre line, the
/// sums of vx and of the grains' mass, and each bin's series of its mean vx and of its
/// velocity variance per sample.
struct ProfileSums {
  std::vector<double> vx, mass;
  std::vector<long long> count;
  std::vector<std::vector<double>> series;  ///< per bin: mean vx of each sample it had grains
  /// per bin: the grains' velocity variance about the bin's mean (x and y summed) per sample
  std::vector<std::vector<double>> fluctuation;
  long long samples = 0;
  void add(const DemSystem& s, double y_bottom, double d, double density) {
    const auto& p = s.particles();
    // this sample's sums per bin (sized to the bins seen so far, grown as grains reach higher)
    sx_.assign(vx.size(), 0.0), sy_.assign(vx.size(), 0.0), s2_.assign(vx.size(), 0.0);
    sm_.assign(vx.size(), 0.0), sn_.assign(vx.size(), 0);
    for (int i = 0; i < s.grains(); ++i) {
      const long k = static_cast<long>(std::floor((p.y[i] - y_bottom) / d));
      if (k < 0) continue;
      const auto b = static_cast<std::size_t>(k);
      if (b >= sn_.size()) {
        for (auto* v : {&sx_, &sy_, &s2_, &sm_}) v->resize(b + 1, 0.0);
        sn_.resize(b + 1, 0);
      }
      sx_[b] += p.vx[i];
      sy_[b] += p.vy[i];
      s2_[b] += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i];
      sm_[b] += density * kPi * p.r[i] * p.r[i];
      ++sn_[b];
    }
    if (sn_.size() > vx.size()) {
      for (auto* v : {&vx, &mass}) v->resize(sn_.size(), 0.0);
      count.resize(sn_.size(), 0);
      series.resize(sn_.size());
      fluctuation.resize(sn_.size());
    }
    for (std::size_t b = 0; b < sn_.size(); ++b) {
      vx[b] += sx_[b], mass[b] += sm_[b], count[b] += sn_[b];
      if (sn_[b] == 0) continue;
      const double n = double(sn_[b]), mx = sx_[b] / n, my = sy_[b] / n;
      series[b].push_back(mx);
      fluctuation[b].push_back(std::max(0.0, s2_[b] / n - mx * mx - my * my));
    }
    ++samples;
  }

 private:
  std::vector<double> sx_, sy_, s2_, sm_;
  std::vector<long long> sn_;
};

/// Least-squares line through the bulk bins of the profile: shear rate, R^2, max deviation / U.
void fit_profile(ShearCellResult& r, double lo, double hi, double speed) {
  double n = 0, sy = 0, sv = 0, syy = 0, syv = 0;
  for (std::size_t k = 0; k < r.profile_y.size(); ++k) {
    const double y = r.profile_y[k], v = r.profile_vx[k];
    if (r.profile_count[k] == 0 || y < lo || y > hi) continue;
    n += 1;
    sy += y;
    sv += v;
    syy += y * y;
    syv += y * v;
  }
  r.bulk_bins = static_cast<int>(n);
  if (n < 3) return;
  const double ym = sy / n, vm = sv / n;
  const double slope = (syv - n * ym * vm) / (syy - n * ym * ym);
  const double a = vm - slope * ym;
  double ss_res = 0, ss_tot = 0, worst = 0;
  for (std::size_t k = 0; k < r.profile_y.size(); ++k) {
    const double y = r.profile_y[k], v = r.profile_vx[k];
    if (r.profile_count[k] == 0 || y < lo || y > hi) continue;
    const double e = v - (a + slope * y);
    ss_res += e * e;
    ss_tot += (v - vm) * (v - vm);
    worst = std::max(worst, std::abs(e));
  }
  r.shear_rate = slope;
  r.profile_r2 = ss_tot > 0 ? 1.0 - ss_res / ss_tot : 0.0;
  r.profile_max_deviation = speed > 0 ? worst / speed : 0.0;
}

/// The area fraction of the grains whose centres lie in the band [lo, hi) of a cell
/// @p width wide (0 for an empty band).
double band_area_fraction(const DemSystem& s, double lo, double hi, double width) {
  const auto& pa = s.particles();
  double area = 0;
  for (int i = 0; i < s.grains(); ++i) {
    if (pa.y[i] >= lo && pa.y[i] < hi) area += kPi * pa.r[i] * pa.r[i];
  }
  return hi > lo ? area / (width * (hi - lo)) : 0.0;
}

/// The window's series (pressure, shear stress, bottom shear stress and pressure, lid height,
/// area fraction), each sample in order.
struct CellSeries {
  const std::vector<double>* p;
  const std::vector<double>* tau;
  const std::vector<double>* tau_bottom;
  const std::vector<double>* p_bottom;
  const std::vector<double>* height;
  const std::vector<double>* phi;
};

/// The block means of the measuring window's series (from r.window_begin on), the friction
/// tau / P, the mean velocity profile and its fit into @p r.
void window_statistics(const ShearCellConfig& c, const CellSeries& x, const ProfileSums& profile,
                       double d, double width, ShearCellResult& r) {
  const std::size_t b = r.window_begin, e = r.samples.size();
  const auto stat = [&](const std::vector<double>* v) { return block_stat(*v, b, e, c.blocks); };
  r.pressure = stat(x.p);
  r.shear_stress = stat(x.tau);
  r.bottom_shear_stress = stat(x.tau_bottom);
  r.bottom_pressure = stat(x.p_bottom);
  r.lid_height = stat(x.height);
  r.area_fraction = stat(x.phi);
  r.friction = block_ratio(*x.tau, *x.p, b, e, c.blocks);
  // the weight per width above each bin's centre: the bins above it and half its own
  double above = 0;
  r.profile_pressure.assign(profile.vx.size(), r.pressure.mean);
  for (std::size_t k = profile.vx.size(); k-- > 0;) {
    const double own = profile.mass[k] / double(std::max(1LL, profile.samples)) / width;
    r.profile_pressure[k] += c.gravity * (above + 0.5 * own);
    above += own;
  }
  for (std::size_t k = 0; k < profile.vx.size(); ++k) {
    r.profile_y.push_back((static_cast<double>(k) + 0.5) * d);
    r.profile_count.push_back(profile.count[k]);
    r.profile_vx.push_back(profile.count[k] ? profile.vx[k] / profile.count[k] : 0.0);
    const BlockMean m = block_mean(profile.series[k], std::size_t(c.blocks));
    r.profile_vx_stderr.push_back(std::isfinite(m.stderr_corrected) ? m.stderr_corrected : 0.0);
    // delta v = sqrt(<variance>), its error by the same rule (d sqrt(x) = dx / (2 sqrt(x)))
    const BlockMean f = block_mean(profile.fluctuation[k], std::size_t(c.blocks));
    const double dv = std::sqrt(std::max(0.0, f.mean));
    r.profile_dv.push_back(std::isfinite(dv) ? dv : 0.0);
    r.profile_dv_stderr.push_back(
        dv > 0 && std::isfinite(f.stderr_corrected) ? 0.5 * f.stderr_corrected / dv : 0.0);
  }
  const double layer = c.wall_layer * d;
  fit_profile(r, layer, r.lid_height.mean - layer, c.wall_speed);
}

/// The mean |psi6| of the grains per bin of @p d above @p y_bottom (@p bins of them), in the
/// system's present state, periodic in x over @p width.
std::vector<double> psi6_profile(const DemSystem& s, double y_bottom, double d, double width,
                                 std::size_t bins) {
  const auto& pa = s.particles();
  const auto n = static_cast<std::size_t>(s.grains());
  const std::vector<double> x(pa.x.begin(), pa.x.begin() + std::ptrdiff_t(n)),
      y(pa.y.begin(), pa.y.begin() + std::ptrdiff_t(n)),
      r(pa.r.begin(), pa.r.begin() + std::ptrdiff_t(n));
  const std::vector<double> order = hexatic_order(x, y, r, width);
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double k = std::floor((y[i] - y_bottom) / d);
    if (k < 0 || k >= double(bins) || !std::isfinite(order[i])) continue;
    sum[std::size_t(k)] += order[i];
    count[std::size_t(k)] += 1;
  }
  for (std::size_t k = 0; k < bins; ++k) sum[k] = count[k] > 0 ? sum[k] / count[k] : std::nan("");
  return sum;
}

}  // namespace

DemConfig shear_cell_dem_config(const ShearCellConfig& c) {
  DemConfig dc = c.grains;
  const double d = dc.grain_diameter;
  dc.xmin = 0;
  dc.xmax = c.width * d;
  dc.ymin = 0;
  dc.ymax = c.height * d;
  dc.periodic_x = true;
  dc.periodic_y = false;
  dc.wall_bottom = dc.wall_top = true;
  dc.wall_left = dc.wall_right = false;
  dc.gravity = {0, -c.gravity};
  dc.intruder_diameter = 0;
  dc.intruder_velocity = {0, 0};
  dc.intruder_omega = 0;
  dc.lid_pressure = c.pressure;
  dc.fields.enabled = false;
  return dc;
}

ShearCellConfig shear_cell_at(const ShearCellConfig& base, double target_I, double strain_scale) {
  ShearCellConfig c = base;
  const double d = c.grains.grain_diameter;
  const double gap = (c.height - 1) * d;  // between the walls' centre lines
  c.wall_speed = target_I * gap * std::sqrt(c.pressure / c.grains.density) / d;
  const double rate = c.wall_speed / gap;  // 1/s, nominal
  const double s_in = (target_I < 0.01 ? 0.5 : 1.0) * strain_scale;
  const double s_win = (target_I < 0.01 ? 1.0 : 2.0) * strain_scale;
  const auto steps = [&](double strain) {
    return static_cast<long long>(std::ceil(strain / (rate * c.grains.dt)));
  };
  c.run_in_steps = steps(s_in);
  c.measure_steps = steps(s_win);
  c.max_run_in_steps = c.run_in_steps + 2 * c.measure_steps;
  c.sample_every = static_cast<int>(std::max(10LL, c.measure_steps / 2000));
  return c;
}

ShearCellResult run_shear_cell(const ShearCellConfig& c, const ProgressCallback& progress) {
  const DemConfig dc = shear_cell_dem_config(c);
  validate(c, dc);
  const double d = dc.grain_diameter, width = dc.xmax - dc.xmin;
  ShearCellResult r;

  const PackedBed bed = prepare_packing(dc, progress);
  r.packed_area_fraction = bed.area_fraction;
  // Start from the linear profile of simple shear (shortens the run-in): vx = U y / H.
  const double y_bottom = dc.ymin + 0.5 * d, y_top = dc.ymax - 0.5 * d;
  std::vector<Disk> grains = grain_disks(dc, bed.x, bed.y, bed.r);
  for (Disk& g : grains) g.vx = c.wall_speed * (g.y - y_bottom) / (y_top - y_bottom);
  DemSystem s(system_options(dc));
  s.set_bodies(grains, make_wall_disks(dc));
  // The lid's damping: c v is a force the grains do not feel, so the window's mean pressure is
  // P + c <v> / W; the lid's height wanders with the bed's dilatancy fluctuations, and with the
  // critical damping of the static bed that term is several % of P (measured +6% and -5% at
  // I ~ 0.1). Unless set, the cell uses kLidDampingFraction of it (the grains damp the rest).
  DemConfig lid_cfg = dc;
  if (!(lid_cfg.lid_damping > 0)) {
    lid_cfg.lid_damping = kLidDampingFraction * PressureLid(dc, s).damping();
  }
  s.attach_lid(PressureLid(lid_cfg, s, c.wall_speed));
  const PressureLid& lid = *s.lid();
  const int bottom_begin = s.grains(), bottom_end = lid.begin();  // make_wall_disks: bottom first
  s.prepare();
  r.grains = s.grains();
  for (int i = 0; i < s.grains(); ++i)
    r.grain_mass += dc.density * kPi * s.particles().r[i] * s.particles().r[i];
  const double ov0 = s.current_max_overlap_fraction();
  if (ov0 > dc.max_overlap_fraction) {
    throw RunFailure("shear cell: the prepared bed overlaps by " + str(ov0) + " of a diameter");
  }

  const double layer = c.wall_layer * d;
  std::vector<double> p, tau, tau_bottom, p_bottom, height, phi;
  ProfileSums profile;
  const long long cap = std::max(c.max_run_in_steps, c.run_in_steps);
  const long long planned = c.run_in_steps + c.measure_steps;
  // Runs n steps, sampling every sample_every; the profile only inside the window.
  auto run = [&](long long n, bool window) {
    for (long long k = 0; k < n;) {
      const long long m = std::min<long long>(c.sample_every, n - k);
      const double t0 = s.time(), ix = lid.state().impulse_x, iy = lid.state().impulse_y;
      s.advance(m);
      k += m;
      r.steps += m;
      if (m < c.sample_every) continue;
      ShearCellSample smp;
      smp.time = s.time();
      // the lid's force averaged over every step since the last sample (exact time average)
      const double span = width * (smp.time - t0);
      smp.pressure = (lid.state().impulse_y - iy) / span;
      smp.shear_stress = -(lid.state().impulse_x - ix) / span;
      const auto bottom = s.frozen_force(bottom_begin, bottom_end);
      smp.bottom_shear_stress = bottom[0] / width;
      smp.bottom_pressure = -bottom[1] / width;
      smp.lid_height = lid.state().y - y_bottom;
      smp.area_fraction = band_area_fraction(s, y_bottom + layer, lid.state().y - layer, width);
      const double ov = s.take_max_overlap_fraction();
      if (!std::isfinite(smp.pressure) || !std::isfinite(smp.shear_stress) ||
          ov > dc.max_overlap_fraction) {
        throw RunFailure("shear cell: step " + str(r.steps) + " (t = " + str(smp.time) +
                         " s): pressure " + str(smp.pressure) + " N/m, overlap " + str(ov) +
                         " of a diameter (max " + str(dc.max_overlap_fraction) + "); reduce dt (" +
                         str(dc.dt) + " s) or U (" + str(c.wall_speed) + " m/s)");
      }
      r.samples.push_back(smp);
      p.push_back(smp.pressure);
      tau.push_back(smp.shear_stress);
      tau_bottom.push_back(smp.bottom_shear_stress);
      p_bottom.push_back(smp.bottom_pressure);
      height.push_back(smp.lid_height);
      phi.push_back(smp.area_fraction);
      if (window) profile.add(s, y_bottom, d, dc.density);
      if (progress) progress(std::min(1.0, static_cast<double>(r.steps) / planned), "shear");
    }
  };

  run(c.run_in_steps, false);
  r.run_in_steps = c.run_in_steps;
  for (;;) {
    r.window_begin = r.samples.size();
    profile = ProfileSums{};
    run(c.measure_steps, true);
    const std::size_t b = r.window_begin, e = r.samples.size();
    r.steady = halves_agree(tau, b, e, c.blocks, c.steady_sigma, &p) &&
               halves_agree(phi, b, e, c.blocks, c.steady_sigma);
    if (r.steady || r.run_in_steps + c.measure_steps > cap) break;
    r.run_in_steps += c.measure_steps;  // this window was still run-in
  }

  window_statistics(c, {&p, &tau, &tau_bottom, &p_bottom, &height, &phi}, profile, d, width, r);
  r.profile_psi6 = psi6_profile(s, y_bottom, d, width, r.profile_y.size());
  r.inertial_number = r.shear_rate * d / std::sqrt(r.pressure.mean / dc.density);
  return r;
}

}  // namespace grainlift::dem
