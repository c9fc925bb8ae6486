// `grainlift calibrate CASE`: the DEM shear-cell calibration of the continuum's mu(I) for the
// case's grains (dem/glue/calibration.cc), written as a rheology file a case can name.
#include <fmt/format.h>

#include <filesystem>

#include "commands.h"
#include "grainlift/shared/case_loader.h"
#include "grainlift/shared/errors.h"
#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/calibration.h"
#endif

namespace grainlift::app {

int cmd_calibrate(const CalibrateArgs& a) {
#ifdef GRAINLIFT_HAVE_DEM
  const Case c = load_case(a.case_path, a.sets);
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
  const MuIFit& f = cal.law.mu_i;
  fmt::print("mu(I): mu_s {:.4f} +- {:.4f}, mu_2 {:.4f} +- {:.4f}, I0 {:.4f} +- {:.4f} "
             "(chi2/dof {:.2g}, {} points, I in [{:.3g}, {:.3g}])\n",
             f.mu_s, f.mu_s_err, f.mu_2, f.mu_2_err, f.I0, f.I0_err, f.chi2_per_dof, f.points,
             cal.law.I_min, cal.law.I_max);
  fmt::print("Phi(I) = {:.4f} - {:.4f} I (+- {:.4f}, {:.4f})\n", cal.law.phi_i.phi_max,
             cal.law.phi_i.a, cal.law.phi_i.phi_max_err, cal.law.phi_i.a_err);
  fmt::print("rheology file: {} (name it in a case: continuum.rheology_file; plot: "
             "scripts/plot_rheology.py {})\n",
             out, out);
  return exit_success;
#else
  (void)a;
  throw InputError("calibrate needs the DEM solver, which this build of grainlift does not have");
#endif
}

}  // namespace grainlift::app
