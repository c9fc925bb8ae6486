// Numbers in the engine's error messages: four significant digits, as a person reads them.
#pragma once

#include <sstream>
#include <string>

namespace grainlift::dem::detail {

/// @brief @p v with four significant digits (for ConfigError / RunFailure messages).
template <class T>
std::string str(T v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace grainlift::dem::detail
