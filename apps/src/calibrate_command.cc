// `grainlift calibrate CASE`: the DEM shear-cell calibration of the continuum's mu(I) for the
// case's grains (dem/glue/calibration.cc), written as a rheology file a case can name.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "python_script.h"
#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/calibration.h"
#endif

namespace grainlift::app {

#ifdef GRAINLIFT_HAVE_DEM
namespace {

/// `calibrate --nonlocal`: the creeping-layer cell, A fitted with the file's mu_s, the
/// [nonlocal] table added to the file and the profile written beside it (.creep.csv).
int calibrate_nonlocal(const CalibrateArgs& a, const Case& c, const std::string& out) {
  if (!std::filesystem::exists(out))
    throw InputError(fmt::format("calibrate --nonlocal: {} does not exist; its mu_s is needed "
                                 "(run `grainlift calibrate {}` first)",
                                 out, a.case_path));
  RheologyFile law = read_rheology_file(out);
  dem::CreepOptions o;
  o.pressure = a.pressure;
  o.threads = a.threads;
  o.seeds = a.seeds;
  o.top_inertial_number = a.creep_inertial_number;
  o.run_in_travel *= a.strain_scale;
  o.window_travel *= a.strain_scale;
  const dem::CreepCalibration cal = dem::calibrate_cooperativity(
      c, o, law.mu_i, [&](const std::string& line) {
        if (a.quiet) return;
        fmt::print("calibrate: {}\n", line);
        std::fflush(stdout);  // a line per bed as it ends, also into a log file
      });
  const CreepProfile& p = cal.profile;
  std::string csv = fmt::format(
      "# grainlift calibrate --nonlocal: {} beds pooled; tau = {} +- {}, mu_s = {}; v_fit at "
      "the pooled profile's A = {}, v_local at the local limit\n"
      "y_m,vx_m_per_s,vx_stderr,pressure,mu,dv_m_per_s,dv_stderr,v_fit,v_local,psi6\n",
      cal.cells.size(), p.shear_stress, p.shear_stress_err, law.mu_i.mu_s,
      cal.profile_fit_amplitude);
  const auto at = [](const std::vector<double>& v, std::size_t k) {
    return k < v.size() ? v[k] : std::nan("");
  };
  for (std::size_t k = 0; k < p.y.size(); ++k)
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", p.y[k], p.vx[k], p.vx_err[k],
                       p.pressure[k], p.shear_stress / p.pressure[k], p.dv[k], p.dv_err[k],
                       at(cal.fit_velocity, k), at(cal.local_velocity, k), at(p.psi6, k));
  const std::string csv_path = std::filesystem::path(out).replace_extension(".creep.csv").string();
  write_text_atomically(csv_path, csv);
  const std::string png = std::filesystem::path(out).replace_extension(".creep.png").string();
  if (run_python_script("plot_creep.py", {csv_path, png}) == 0)
    fmt::print("profile: {} (plot {})\n", csv_path, png);
  else
    fmt::print("profile: {} (plot not drawn: scripts/plot_creep.py failed)\n", csv_path);
  const CooperativityFit& f = cal.fit;
  if (!f.ok)
    throw RunError(fmt::format("calibrate --nonlocal: A not determined: {} (chi2/dof {:.2f}, "
                               "{} bins, C {:.3f}); {} left as it was",
                               f.message, f.chi2_per_dof, f.points, f.scale, out));
  law.nonlocal = Cooperativity{f.amplitude, f.amplitude_err, f.chi2_per_dof, f.points,
                               f.mu_min, f.mu_max};
  law.source["nonlocal"] = fmt::format(
      "calibrate --nonlocal: {} beds of {} d x {} d, p at the bottom {} P, travel {} + {} d; "
      "grainlift {} ({})",
      cal.cells.size(), o.width, o.height, o.bottom_pressure_ratio, o.run_in_travel,
      o.window_travel, grainlift_version(), grainlift_git_revision());
  write_rheology_file(out, law);
  fmt::print("cooperativity: A {:.3f} +- {:.3f} ({}: {:.3f}; mu_s's part {:.3f}); pooled "
             "profile: A {:.3f}, chi2/dof {:.2f}, {} bins, mu {:.3f}-{:.3f}, velocity {:.3f} x "
             "the calibrated law's, floor {:.2g} m/s\nrheology file: {} ([nonlocal])\n",
             f.amplitude, f.amplitude_err,
             cal.cells.size() > 1 ? "the beds' pooled mean and error" : "the profile's error",
             f.profile_err, f.mu_s_err_part, cal.profile_fit_amplitude, f.chi2_per_dof,
             f.points, f.mu_min, f.mu_max, f.scale, f.floor, out);
  return exit_success;
}

}  // namespace
#endif

int cmd_calibrate(const CalibrateArgs& a) {
#ifdef GRAINLIFT_HAVE_DEM
  // the case's own continuum law plays no part here, and the file it names may be the one this
  // calibration is about to write
  auto sets = a.sets;
  sets.push_back("continuum.rheology_file=\"\"");
  const Case c = load_case(a.case_path, sets);
  dem::CalibrationOptions o;
  o.pressure = a.pressure;
  if (!a.inertial_numbers.empty()) o.inertial_numbers = a.inertial_numbers;
  o.strain_scale = a.strain_scale;
  o.threads = a.threads;
  const std::string out = a.out.empty()
                              ? (std::filesystem::path(a.case_path).parent_path() / "rheology.toml")
                                    .string()
                              : a.out;
  if (a.nonlocal) return calibrate_nonlocal(a, c, out);
  const dem::Calibration cal = dem::calibrate_rheology(c, o, [&](const std::string& line) {
    if (a.quiet) return;
    fmt::print("calibrate: {}\n", line);
    std::fflush(stdout);
  });
  write_rheology_file(out, cal.law);
  RheologyFile law = cal.law;
  if (!a.wall_runs.empty()) {  // the wall law, fitted by the Python package into [wall]
    std::vector<std::string> args = {out};
    args.insert(args.end(), a.wall_runs.begin(), a.wall_runs.end());
    const int code = run_python_script("fit_wall.py", args);
    if (code != 0)
      throw RunError(fmt::format("calibrate --wall: {} failed (exit {}); {} holds mu(I) and "
                                 "Phi(I) without [wall]",
                                 script_path("fit_wall.py"), code, out));
    law = read_rheology_file(out);
  }
  // the cache makes it the continuum's default law for these grains (rheology_cache.h)
  const double pressure = a.pressure > 0 ? a.pressure : c.continuum_pressure();
  const std::string cached = rheology_cache_path(c, pressure);
  if (!cached.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(cached).parent_path(), ec);
    try {
      cache_rheology(cached, law);
    } catch (const RunError& e) {  // the cache is an optimisation: say so, keep the result
      fmt::print("calibrate: not cached ({})\n", e.what());
    }
  }
  const std::string png = std::filesystem::path(out).replace_extension(".png").string();
  const bool plotted = run_python_script("plot_rheology.py", {out, png}) == 0;
  const MuIFit& f = cal.law.mu_i;
  fmt::print("mu(I): mu_s {:.4f} +- {:.4f}, mu_2 {:.4f} +- {:.4f}, I0 {:.4f} +- {:.4f} "
             "(chi2/dof {:.2g}, {} points, I in [{:.3g}, {:.3g}])\n",
             f.mu_s, f.mu_s_err, f.mu_2, f.mu_2_err, f.I0, f.I0_err, f.chi2_per_dof, f.points,
             cal.law.I_min, cal.law.I_max);
  fmt::print("Phi(I) = {:.4f} - {:.4f} I (+- {:.4f}, {:.4f})\n", cal.law.phi_i.phi_max,
             cal.law.phi_i.a, cal.law.phi_i.phi_max_err, cal.law.phi_i.a_err);
  fmt::print("rheology file: {} (name it in a case: continuum.rheology_file)\n", out);
  if (!cached.empty())
    fmt::print("cached: {} (runs of cases with these grains at {:g} Pa that state no mu(I) of "
               "their own use it)\n",
               cached, pressure);
  if (plotted) fmt::print("plot: {}\n", png);
  else fmt::print("plot: not drawn ({} scripts/plot_rheology.py {} failed)\n", python_path(), out);
  return exit_success;
#else
  (void)a;
  throw InputError("calibrate needs the DEM solver, which this build of grainlift does not have");
#endif
}

}  // namespace grainlift::app
