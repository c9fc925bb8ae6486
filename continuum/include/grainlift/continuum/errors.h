// Errors raised by the continuum engine. Non-convergence is not an error: it is
// reported in ContinuumOutput::converged / ContinuumOutput::message.
#pragma once

#include <stdexcept>
#include <string>

namespace grainlift::continuum {

/// @brief A ContinuumConfig value is out of range or inconsistent (names the field).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace grainlift::continuum
