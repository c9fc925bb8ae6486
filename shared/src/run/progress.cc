#include "grainlift/shared/run/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <mutex>

namespace grainlift {

namespace {
/// Held while a reporter writes: lines of reporters on different threads do not interleave.
std::mutex print_mutex;
}  // namespace

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 60) return fmt::format("{:.1f}s", s);
  const long t = std::lround(s);
  if (t < 3600) return fmt::format("{}m{:02d}s", t / 60, int(t % 60));
  return fmt::format("{}h{:02d}m", t / 3600, int((t % 3600) / 60));
}

ProgressReporter::ProgressReporter(std::string label, bool enabled, bool own_line)
    : label_(std::move(label)), enabled_(enabled),
      tty_(own_line && ::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()), phase_start_(start_), last_print_(start_) {}

void ProgressReporter::update(double fraction, const std::string& phase,
                              const std::string& detail) {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(print_mutex);
  const auto now = std::chrono::steady_clock::now();
  if (phase != phase_) {
    if (open_line_) std::fputc('\n', stderr);
    open_line_ = false;
    phase_ = phase;
    phase_start_ = now;
    last_decile_ = -1;
  }
  fraction = std::min(1.0, std::max(0.0, fraction));
  const double elapsed = std::chrono::duration<double>(now - phase_start_).count();
  const double eta = fraction > 1e-6 ? elapsed * (1 - fraction) / fraction : NAN;
  std::string line =
      fmt::format("[{}] {:<8} {:5.1f}%  elapsed {}  ETA {}", label_, phase, 100 * fraction,
                  format_duration(elapsed), fraction > 1e-6 ? format_duration(eta) : "?");
  if (!detail.empty()) line += "  " + detail;
  if (tty_) {
    if (std::chrono::duration<double>(now - last_print_).count() < 0.2 && fraction < 1) return;
    std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
    open_line_ = true;
  } else {
    const int decile = int(std::floor(fraction * 10));
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
  last_print_ = now;
}

void ProgressReporter::message(const std::string& text) {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(print_mutex);
  if (open_line_) std::fputc('\n', stderr);
  open_line_ = false;
  std::fprintf(stderr, "[%s] %s\n", label_.c_str(), text.c_str());
  std::fflush(stderr);
}

void ProgressReporter::finish() {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(print_mutex);
  if (open_line_) std::fputc('\n', stderr);
  open_line_ = false;
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "[%s] done in %s\n", label_.c_str(), format_duration(total).c_str());
  std::fflush(stderr);
}

}  // namespace grainlift
