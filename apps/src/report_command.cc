// `grainlift report DIR`: one HTML page on a result folder (DIR/report.html with its PNGs beside
// it), drawn by scripts/report.py; this command only checks the folder and runs the script.
#include <fmt/format.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "commands.h"
#include "grainlift/shared/errors.h"

#ifndef GRAINLIFT_REPORT_SCRIPT
#error "GRAINLIFT_REPORT_SCRIPT (absolute path of scripts/report.py) is set by apps/CMakeLists.txt"
#endif
#ifndef GRAINLIFT_PYTHON
#define GRAINLIFT_PYTHON "/usr/bin/python3"
#endif

namespace grainlift::app {
namespace {

/// @p s in single quotes for /bin/sh; a path with a single quote is refused (InputError).
std::string shell_quoted(const std::string& s, const char* what) {
  if (s.find('\'') != std::string::npos)
    throw InputError(fmt::format("report: {} '{}' contains a single quote, which this command "
                                 "does not pass to the shell; rename or link the folder",
                                 what, s));
  return "'" + s + "'";
}

}  // namespace

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
  const std::string command = fmt::format(
      "{} {} {}", shell_quoted(GRAINLIFT_PYTHON, "python"),
      shell_quoted(GRAINLIFT_REPORT_SCRIPT, "script"), shell_quoted(dir, "folder"));
  const int status = std::system(command.c_str());
  if (status == -1) throw RunError(fmt::format("report: could not start {}", command));
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code != 0)
    throw RunError(fmt::format("report: {} failed (exit {}){}", GRAINLIFT_REPORT_SCRIPT, code,
                               code == 127 ? "; is " GRAINLIFT_PYTHON " installed, with h5py "
                                             "and matplotlib?"
                                           : ""));
  fmt::print("report: {}\n", (fs::path(dir) / "report.html").string());
  return exit_success;
}

}  // namespace grainlift::app
