// The choice of the SIMD target (simd_target.h) and the names the user sees: Highway's
// targets as lower-case names (AVX3, Highway's AVX-512 target, is called avx512), our own
// scalar code as "scalar".
#include "step/simd_target.h"

#include <hwy/targets.h>

#include <atomic>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "grainlift/dem/step/vector_kernels.h"
#include "step/step_kernels.h"

namespace grainlift::dem::detail {

namespace {

// The vector targets of this build: those Highway compiles the kernels for (HWY_TARGETS of
// this translation unit equals theirs: the same compiler flags and HWY_DISABLED_TARGETS, set
// in dem/CMakeLists.txt), without Highway's own scalar fallbacks and without 32-bit Arm's
// NEON, which has no lanes of doubles.
constexpr std::int64_t kBuilt =
    HWY_TARGETS & ~(HWY_SCALAR | HWY_EMU128) & ~(HWY_ARCH_ARM_V7 ? HWY_NEON : 0);

std::string name_of(std::int64_t target) {
  if (target == HWY_AVX3) return "avx512";
  std::string s = hwy::TargetName(target);
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

/// The targets of this build that this CPU runs, read before any choice narrows what
/// Highway reports.
std::int64_t runnable() {
  static const std::int64_t cpu = hwy::SupportedTargets() & kBuilt;
  return cpu;
}

/// One target per bit of @p mask, the least capable first (Highway: a lower bit is better).
std::vector<std::int64_t> each(std::int64_t mask) {
  std::vector<std::int64_t> out;
  for (int b = 62; b >= 0; --b) {
    if (mask & (std::int64_t{1} << b)) out.push_back(std::int64_t{1} << b);
  }
  return out;
}

/// The target @p want names: a Highway target bit, 0 for our scalar code ("scalar", or "auto"
/// on a CPU without any of this build's vector targets), -1 when this build or CPU cannot
/// run it.
std::int64_t parse(const std::string& want) {
  if (want == "scalar") return 0;
  const std::int64_t cpu = runnable();
  if (want == "auto") return cpu & -cpu;  // the lowest bit: the best target
  for (const std::int64_t t : each(cpu)) {
    if (name_of(t) == want) return t;
  }
  return -1;
}

std::atomic<std::int64_t> g_target{0};
std::atomic<bool> g_allowed{true};

/// Make @p target the one HWY_DYNAMIC_DISPATCH calls (0: no vector loop runs at all).
/// Highway dispatches to the best target it is not told to leave out, so every other one is
/// left out, and the choice is made now: Highway 1.0's SupportedTargets() sets it back to the
/// CPU's best (this file calls that once, in runnable(), before any choice).
void use(std::int64_t target) {
  if (target != 0) {
    hwy::DisableTargets(~target);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
  }
  g_target.store(target, std::memory_order_relaxed);
}

/// The target in use, chosen from the environment at the first call; a target that is not
/// there falls back to scalar (and the run refuses to start: simd_setting_error).
std::int64_t target() {
  static const bool chosen = [] {
    const std::int64_t t = parse(requested_simd());
    use(t < 0 ? 0 : t);
    return true;
  }();
  (void)chosen;
  return g_target.load(std::memory_order_relaxed);
}

}  // namespace

bool vector_enabled() {
  return target() != 0 && g_allowed.load(std::memory_order_relaxed);
}

std::string requested_simd() {
  if (std::getenv("GRAINLIFT_NO_SIMD")) return "scalar";  // the older switch
  const char* s = std::getenv("GRAINLIFT_SIMD");
  return s && *s ? std::string(s) : std::string("auto");
}

}  // namespace grainlift::dem::detail

namespace grainlift::dem {

void set_vector_kernels(bool on) { detail::g_allowed.store(on, std::memory_order_relaxed); }

bool vector_kernels() { return detail::vector_enabled(); }

std::string simd_target() {
  // the target whose code the dispatch calls, as that code names itself
  return detail::vector_enabled() ? detail::name_of(detail::dispatched_target()) : "scalar";
}

std::vector<std::string> runnable_simd_targets() {
  std::vector<std::string> names = {"scalar"};
  for (const std::int64_t t : detail::each(detail::runnable()))
    names.push_back(detail::name_of(t));
  return names;
}

std::string simd_targets() {
  std::string s;
  for (const std::string& n : runnable_simd_targets()) s += (s.empty() ? "" : ", ") + n;
  std::string lacking;
  for (const std::int64_t t : detail::each(detail::kBuilt & ~detail::runnable()))
    lacking += (lacking.empty() ? "" : ", ") + detail::name_of(t);
  if (!lacking.empty()) s += " (also built, not run by this CPU: " + lacking + ")";
  return s;
}

bool set_simd_target(const std::string& name) {
  const std::int64_t t = detail::parse(name);
  if (t < 0) return false;
  detail::target();  // the first choice made, so that it cannot undo this one
  detail::use(t);
  return true;
}

std::string simd_setting_error() {
  const std::string want = detail::requested_simd();
  if (detail::parse(want) >= 0) return {};
  return "GRAINLIFT_SIMD=" + want + ": the DEM's vector targets here are " + simd_targets() +
         "; unset it (the best the CPU runs) or name one of them";
}

}  // namespace grainlift::dem
