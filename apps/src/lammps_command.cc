// `grainlift export lammps` and `grainlift import lammps`: the LAMMPS bridge
// (dem/glue/lammps_export.cc, lammps_import.cc; docs/lammps.md).
#include <fmt/format.h>

#include "commands.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/lammps_bridge.h"
#endif

namespace grainlift::app {

int cmd_export_lammps(const std::string& case_path, const std::vector<std::string>& sets,
                      const std::string& dir) {
#ifdef GRAINLIFT_HAVE_DEM
  const Case c = load_case(case_path, sets);
  const dem::LammpsExport ex = dem::export_lammps(c, dir);
  fmt::print("export lammps: {} grains, {} wall disks, area fraction {:.4f} (packing {}), {} "
             "steps\n  {}/{}  {}/{}\n  run:    cd {} && lmp -in {}   (or mpirun -np N lmp -in {})\n"
             "  then:   grainlift import lammps {} --out OUT\n",
             ex.grains, ex.walls, ex.area_fraction,
             ex.packing_from_cache ? "reused from cache" : "prepared", ex.steps, dir,
             dem::kLammpsScript, dir, dem::kLammpsData, dir, dem::kLammpsScript,
             dem::kLammpsScript, dir);
  return 0;
#else
  (void)case_path, (void)sets, (void)dir;
  throw InputError("export lammps needs the DEM, which this build of grainlift lacks");
#endif
}

int cmd_import_lammps(const std::string& dir, const std::string& out) {
#ifdef GRAINLIFT_HAVE_DEM
  const Case c = dem::exported_case(dir);
  SolverEntry lammps{"dem", "LAMMPS's run of an exported case, read back",
                     [&](const Case& cs, const RunOptions&, ProgressReporter&) {
                       return dem::import_lammps(cs, dir);
                     }};
  RunOptions opt;
  opt.out_dir = out;
  opt.progress = false;
  const auto results = run_solvers(c, {lammps}, opt);
  const RunResult& r = results.front();
  if (r.means)
    fmt::print("import lammps: {}/dem.h5: drag {:.6g} +- {:.2g} N/m, lift {:.6g} +- {:.2g} N/m "
               "({} samples{})\n",
               out, r.means->drag, r.means->drag_stderr.value_or(0.0), r.means->lift,
               r.means->lift_stderr.value_or(0.0), r.means->samples,
               r.meta.partial ? "; the LAMMPS run did not finish: partial" : "");
  else
    fmt::print("import lammps: {}/dem.h5: no sample after the steady start\n", out);
  return 0;
#else
  (void)dir, (void)out;
  throw InputError("import lammps needs the DEM, which this build of grainlift lacks");
#endif
}

}  // namespace grainlift::app
