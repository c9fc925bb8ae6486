// `grainlift report DIR`: one HTML page on a result folder (DIR/report.html with its PNGs beside
// it), drawn by scripts/report.py; this command only checks the folder and runs the script.
#include <fmt/format.h>

#include <filesystem>

#include "commands.h"
#include "grainlift/shared/errors.h"
#include "python_script.h"

namespace grainlift::app {

int cmd_report(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir))
    throw InputError(fmt::format("report: '{}' is not a folder (expected a result folder with "
                                 "dem.h5 and/or fem.h5, as written by grainlift run --out)",
                                 dir));
  if (!fs::exists(fs::path(dir) / "dem.h5") && !fs::exists(fs::path(dir) / "fem.h5"))
    throw InputError(fmt::format("report: '{}' holds neither dem.h5 nor fem.h5: run a case into "
                                 "it first (grainlift run CASE --out {})",
                                 dir, dir));
  const int code = run_python_script("report.py", {dir});
  if (code != 0)
    throw RunError(fmt::format("report: {} failed (exit {}){}", script_path("report.py"), code,
                               code == 127 ? fmt::format("; is {} installed, with h5py and "
                                                         "matplotlib?",
                                                         python_path())
                                           : std::string()));
  fmt::print("report: {}\n", (fs::path(dir) / "report.html").string());
  return exit_success;
}

}  // namespace grainlift::app
