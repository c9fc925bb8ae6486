// The two kinds of failure a user can meet, mapped to the documented exit codes by apps/.
#pragma once

#include <stdexcept>
#include <string>

namespace grainlift {

/// Bad input: a case file, an option, an unreadable file. Exit code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A run that failed: diverged, did not converge, blew up. Exit code 1.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr int exit_success = 0;
inline constexpr int exit_run_failed = 1;
inline constexpr int exit_bad_input = 2;

}  // namespace grainlift
