// Progress with an ETA on stderr for long runs: a self-rewriting line on a terminal, one line
// per 10% otherwise (logs, CI).
#pragma once

#include <chrono>
#include <string>

namespace grainlift {

class ProgressReporter {
 public:
  /// @param label prefix such as "dem"; @param enabled false silences it; @param own_line
  /// false: one line per 10% on a terminal too (reporters of solvers that run side by side
  /// would overwrite each other's line). Reporters print whole lines, one at a time.
  ProgressReporter(std::string label, bool enabled, bool own_line = true);
  /// @param fraction done in [0, 1]; @param phase short name ("packing", "run", "newton").
  /// @param detail appended to the line (a current error, ...); changing it starts no new line.
  void update(double fraction, const std::string& phase, const std::string& detail = "");
  /// A free-form line (kept short), printed above the progress line.
  void message(const std::string& text);
  /// Ends the progress line.
  void finish();

 private:
  std::string label_, phase_;
  bool enabled_, tty_;
  std::chrono::steady_clock::time_point start_, phase_start_, last_print_;
  int last_decile_ = -1;
  bool open_line_ = false;
};

/// "1h02m", "3m05s", "12.3s".
std::string format_duration(double seconds);

}  // namespace grainlift
