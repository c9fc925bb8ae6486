// `grainlift calibrate` (calibration.h): shear-cell sweep on the case's grains, then the fit.
#include "grainlift/dem/calibration.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/scenes/shear_cell.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/run_driver.h"

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

Calibration calibrate_rheology(const Case& c, const CalibrationOptions& o,
                               const std::function<void(const std::string&)>& say) {
  const ShearCellConfig base = case_shear_cell(c, o.pressure, o.threads, o.width, o.height);
  const double pressure = base.pressure;
  Calibration cal;
  std::vector<ShearPoint> fit_points;
  // One point: run, report, keep. Returns false when the cell could not run it.
  auto measure = [&](double target, const std::string& note) {
    const auto t0 = std::chrono::steady_clock::now();
    CalibrationPoint p;
    p.target_I = target;
    ShearCellResult r;
    try {
      r = run_shear_cell(shear_cell_at(base, target, o.strain_scale));
    } catch (const ConfigError& e) {
      throw InputError(
          fmt::format("{}: shear cell at I = {}: {}", c.source.path, target, e.what()));
    } catch (const RunFailure& e) {
      p.failure = e.what();
    }
    p.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!p.failure.empty()) {
      say(fmt::format("I target {:<6.3g} FAILED, left out of the fit ({:.1f} s){}: {}", target,
                      p.wall_seconds, note, p.failure));
      cal.points.push_back(p);
      return false;
    }
    p.point = {r.inertial_number, r.friction.mean, r.friction.se, r.area_fraction.mean,
               r.area_fraction.se};
    p.steady = r.steady;
    p.profile_r2 = r.profile_r2;
    p.fitted = r.profile_r2 >= o.min_profile_r2 && p.point.mu_stderr > 0 && p.point.phi_stderr > 0;
    say(fmt::format("I target {:<6.3g} measured {:.4g}: mu {:.4f} +- {:.4f}, Phi {:.4f} +- "
                    "{:.4f}, profile R^2 {:.3f}{}{} ({:.1f} s){}",
                    target, p.point.I, p.point.mu, p.point.mu_stderr, p.point.phi,
                    p.point.phi_stderr, p.profile_r2, p.steady ? "" : ", NOT steady",
                    p.fitted ? "" : ", shear-banded or no error: left out of the fit",
                    p.wall_seconds, note));
    if (p.fitted) fit_points.push_back(p.point);
    cal.points.push_back(p);
    return true;
  };
  // A target the cell cannot run (too fast for soft grains: overlaps) above one it ran is
  // tried once more half way between them on a log scale, so the fit keeps the upper end of
  // the range the grains allow (mu_2 and I0 are set there).
  double last_run = 0;
  for (const double target : o.inertial_numbers) {
    if (measure(target, "")) {
      last_run = target;
      continue;
    }
    if (last_run > 0 && last_run < target) {
      const double between = std::sqrt(last_run * target);
      if (measure(between, fmt::format(" (between {:g} and {:g}, which the cell could not run)",
                                       last_run, target)))
        last_run = between;
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
