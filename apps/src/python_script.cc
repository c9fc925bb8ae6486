#include "python_script.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "grainlift/shared/errors.h"

#ifndef GRAINLIFT_SCRIPT_DIR
#error "GRAINLIFT_SCRIPT_DIR (absolute path of scripts/) is set by apps/CMakeLists.txt"
#endif
#ifndef GRAINLIFT_INSTALLED_SCRIPT_DIR
#define GRAINLIFT_INSTALLED_SCRIPT_DIR "../share/grainlift"
#endif
#ifndef GRAINLIFT_PYTHON
#define GRAINLIFT_PYTHON "/usr/bin/python3"
#endif

namespace grainlift::app {
namespace {

/// @p s in single quotes for /bin/sh; a path with a single quote is refused (InputError).
std::string shell_quoted(const std::string& s) {
  if (s.find('\'') != std::string::npos)
    throw InputError(fmt::format("'{}' contains a single quote, which grainlift does not pass to "
                                 "the shell; rename or link it",
                                 s));
  return "'" + s + "'";
}

}  // namespace

std::string script_path(const std::string& script) {
  // an installed grainlift (cmake --install) runs its scripts from PREFIX/share/grainlift,
  // beside its bin/; one in the build tree, where there is no such folder, from the sources
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed =
        (exe.parent_path() / GRAINLIFT_INSTALLED_SCRIPT_DIR / script).lexically_normal();
    if (std::filesystem::is_regular_file(installed, ec)) return installed.string();
  }
  return std::string(GRAINLIFT_SCRIPT_DIR) + "/" + script;
}

std::string python_path() { return GRAINLIFT_PYTHON; }

int run_python_script(const std::string& script, const std::vector<std::string>& args) {
  std::string command = shell_quoted(python_path()) + " " + shell_quoted(script_path(script));
  for (const auto& a : args) command += " " + shell_quoted(a);
  const int status = std::system(command.c_str());
  if (status == -1) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace grainlift::app
