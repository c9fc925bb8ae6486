// Running one of the project's plotting scripts (scripts/*.py) with the configured python.
#pragma once

#include <string>
#include <vector>

namespace grainlift::app {

/// @brief Runs scripts/@p script with GRAINLIFT_PYTHON and @p args (each passed quoted).
/// @return the script's exit code (127: python could not be started).
/// @throws InputError when an argument holds a single quote (not passed to the shell).
int run_python_script(const std::string& script, const std::vector<std::string>& args);

/// @brief The absolute path of scripts/@p script in the source tree this binary was built from.
std::string script_path(const std::string& script);

/// @brief The configured python interpreter (GRAINLIFT_PYTHON).
std::string python_path();

}  // namespace grainlift::app
