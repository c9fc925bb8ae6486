// `grainlift calibrate` (calibration.h): shear-cell sweep on the case's grains, then the fit.
#include "grainlift/dem/calibration.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <vector>

#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/scenes/shear_cell.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/run_driver.h"
#include "grainlift/shared/run/side_by_side.h"

namespace grainlift::dem {

ShearCellConfig case_shear_cell(const Case& c, double pressure, int threads, double width,
                                double height) {
  if (!(pressure > 0)) pressure = c.continuum_pressure();
  if (!(pressure > 0))
    throw InputError(fmt::format(
        "{}: calibrate needs a pressure: the case has no lid, no gravity and no "
        "continuum.ambient_pressure; give one with --pressure",
        c.source.path));
  ShearCellConfig cell;
  cell.grains = make_dem_config(c, threads);
  cell.width = width;
  cell.height = height;
  cell.pressure = pressure;
  return cell;
}

namespace {
/// The line `calibrate` prints for a point (@p note: why it was measured, or "").
std::string point_line(const CalibrationPoint& p, const std::string& note) {
  if (!p.failure.empty()) {
    return fmt::format("I target {:<6.3g} FAILED, left out of the fit ({:.1f} s){}: {}",
                       p.target_I, p.wall_seconds, note, p.failure);
  }
  return fmt::format("I target {:<6.3g} measured {:.4g}: mu {:.4f} +- {:.4f}, Phi {:.4f} +- "
                     "{:.4f}, profile R^2 {:.3f}{}{} ({:.1f} s){}",
                     p.target_I, p.point.I, p.point.mu, p.point.mu_stderr, p.point.phi,
                     p.point.phi_stderr, p.profile_r2, p.steady ? "" : ", NOT steady",
                     p.fitted ? "" : ", shear-banded or no error: left out of the fit",
                     p.wall_seconds, note);
}
}  // namespace

Calibration calibrate_rheology(const Case& c, const CalibrationOptions& o,
                               const std::function<void(const std::string&)>& say) {
  const ShearCellConfig base = case_shear_cell(c, o.pressure, o.threads, o.width, o.height);
  const double pressure = base.pressure;
  Calibration cal;
  std::vector<ShearPoint> fit_points;
  // One point on @p cell: run and measure (a cell that cannot run it: the point's failure).
  auto run_point = [&](const ShearCellConfig& cell, double target) {
    const auto t0 = std::chrono::steady_clock::now();
    CalibrationPoint p;
    p.target_I = target;
    ShearCellResult r;
    try {
      r = run_shear_cell(shear_cell_at(cell, target, o.strain_scale));
    } catch (const ConfigError& e) {
      throw InputError(
          fmt::format("{}: shear cell at I = {}: {}", c.source.path, target, e.what()));
    } catch (const RunFailure& e) {
      p.failure = e.what();
    }
    p.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!p.failure.empty()) return p;
    p.point = {r.inertial_number, r.friction.mean, r.friction.se, r.area_fraction.mean,
               r.area_fraction.se};
    p.steady = r.steady;
    p.profile_r2 = r.profile_r2;
    p.fitted = r.profile_r2 >= o.min_profile_r2 && p.point.mu_stderr > 0 && p.point.phi_stderr > 0;
    return p;
  };
  auto keep = [&](const CalibrationPoint& p) {
    if (p.failure.empty() && p.fitted) fit_points.push_back(p.point);
    cal.points.push_back(p);
  };
  // The targets side by side, as many at once as there are threads (a cell of a few hundred
  // grains gains little from a team of threads; independent cells about one core each),
  // reported in order; the DEM gives the same bits on any number of threads, so the points
  // are those of one after the other. A bed not cached yet is packed (and cached) by the
  // first point alone, so that the others load it instead of each packing it again.
  const std::size_t n = o.inertial_numbers.size();
  std::vector<CalibrationPoint> first(n);
  const int workers = std::max(1, std::min(o.threads, static_cast<int>(n)));
  ShearCellConfig each = base;
  each.grains.threads = std::max(1, o.threads / workers);
  std::size_t from = 0;
  if (n > 1 && workers > 1) {
    const ShearCellConfig cell0 = shear_cell_at(base, o.inertial_numbers[0], o.strain_scale);
    const std::string bed = packing_cache_path(shear_cell_dem_config(cell0));
    if (!bed.empty() && !std::filesystem::exists(bed)) {
      first[0] = run_point(base, o.inertial_numbers[0]);
      say(point_line(first[0], ""));
      from = 1;
    }
  }
  side_by_side(
      n - from, workers,
      [&](std::size_t k) { first[from + k] = run_point(each, o.inertial_numbers[from + k]); },
      [&](std::size_t k) { say(point_line(first[from + k], "")); });
  // A target the cell cannot run (too fast for soft grains: overlaps) above one it ran is
  // tried once more half way between them on a log scale, so the fit keeps the upper end of
  // the range the grains allow (mu_2 and I0 are set there).
  double last_run = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double target = o.inertial_numbers[k];
    keep(first[k]);
    if (first[k].failure.empty()) {
      last_run = target;
      continue;
    }
    if (last_run > 0 && last_run < target) {
      const double between = std::sqrt(last_run * target);
      const CalibrationPoint p = run_point(base, between);
      say(point_line(p, fmt::format(" (between {:g} and {:g}, which the cell could not run)",
                                    last_run, target)));
      keep(p);
      if (p.failure.empty()) last_run = between;
    }
  }
  if (fit_points.size() < 4)
    throw InputError(fmt::format(
        "{}: the mu(I) fit needs at least 4 shear-cell points with a linear velocity profile; "
        "{} of the {} measured have one (R^2 >= {}): give more or other --inertial-numbers",
        c.source.path, fit_points.size(), cal.points.size(), o.min_profile_r2));
  const DemConfig& g = base.grains;
  cal.law = make_rheology_file(
      fit_points,
      {{"case", c.source.path},
       {"grains", fmt::format("d {} m, polydispersity {}, density {} kg/m^2, law {}, friction {}",
                              g.grain_diameter, g.polydispersity, g.density,
                              c.grains.contact.law, g.contact.friction)},
       {"pressure", fmt::format("{} Pa", pressure)},
       {"cell", fmt::format("{} d x {} d, strain scale {}", o.width, o.height, o.strain_scale)},
       {"grainlift", grainlift_version() + " (" + grainlift_git_revision() + ")"}});
  return cal;
}

}  // namespace grainlift::dem
