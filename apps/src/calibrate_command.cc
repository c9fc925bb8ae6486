// `grainlift calibrate CASE`: the DEM shear-cell calibration of the continuum's mu(I) for the
// case's grains (dem/glue/calibration.cc), written as a rheology file a case can name.
#include <fmt/format.h>

#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "python_script.h"
#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/calibration.h"
#endif

namespace grainlift::app {

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
  const dem::Calibration cal = dem::calibrate_rheology(c, o, [&](const std::string& line) {
    if (!a.quiet) fmt::print("calibrate: {}\n", line);
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
