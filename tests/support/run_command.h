// Runs a shell command for the tests that drive the real `grainlift` binary (or mpirun), and
// returns its exit code and its standard output and error together.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace grainlift::test_support {

struct CommandOutcome {
  int code = -1;       ///< exit status; -1 when the command could not run or was killed
  std::string output;  ///< stdout and stderr
};

inline CommandOutcome run_command(const std::string& command) {
  CommandOutcome o;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return o;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), int(buf.size()), p)) o.output += buf.data();
  const int status = ::pclose(p);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

/// `grainlift ARGS`, the binary of this build.
inline CommandOutcome run_grainlift(const std::string& args) {
  return run_command(std::string(GRAINLIFT_BINARY) + " " + args);
}

}  // namespace grainlift::test_support
