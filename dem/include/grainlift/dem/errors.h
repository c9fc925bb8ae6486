// Errors thrown by the DEM engine. The glue maps ConfigError to exit code 2 and RunFailure to 1.
#pragma once

#include <stdexcept>
#include <string>

namespace grainlift::dem {

/// A configuration the engine refuses before running (bad ranges, dt too large, ...).
/// The message names the offending numbers and the accepted range.
struct ConfigError : std::runtime_error {
  explicit ConfigError(const std::string& what) : std::runtime_error(what) {}
};

/// A run that blew up while integrating (non-finite state, overlap beyond the stated
/// fraction of a diameter), or a bed that cannot fit in memory. The message names the step,
/// the time and the numbers (or the memory needed and the limit).
struct RunFailure : std::runtime_error {
  explicit RunFailure(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace grainlift::dem
