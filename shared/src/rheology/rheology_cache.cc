#include "grainlift/shared/rheology/rheology_cache.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/atomic_file.h"

namespace grainlift {

namespace {

// Format 2: the checksum and the keys are the case hash's FNV-1a (case_loader.h, the standard
// offset basis); format 1 used a mistyped basis, so its entries carry other keys and are not
// found (a run recalibrates), and one found by name is "of another cache format".
constexpr std::string_view kCacheLine = "# grainlift cache 2 fnv1a64 ";

/// The cache entry @p path, read once: its last line's checksum against the bytes above it,
/// then its contents as a rheology file into @p law; what is wrong with it ("" when sound).
std::string read_cache_entry(const std::string& path, RheologyFile& law) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buf;
  buf << in.rdbuf();
  if (!in) return "it cannot be read";
  const std::string text = buf.str();
  const std::size_t last = text.rfind('\n', text.size() >= 2 ? text.size() - 2 : 0);
  const std::size_t start = last == std::string::npos ? 0 : last + 1;
  const std::string_view tail = std::string_view(text).substr(start);
  if (tail.rfind("# grainlift cache ", 0) == 0) {
    if (tail.rfind(kCacheLine, 0) != 0) return "it is of another cache format";
    const std::string want = fnv1a64_hex(text.substr(0, start));
    if (tail.substr(kCacheLine.size(), 16) != want) return "its checksum does not match";
  }
  try {
    law = read_rheology_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

std::string cache_folder(const std::string& setting, const std::string& kind) {
  if (setting.empty()) return {};
  if (setting != "auto") return kind == "packings" ? setting : setting + "/" + kind;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/grainlift/" + kind;
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/grainlift/" + kind;
  return {};
}

std::string grain_material_key(const Case& c, double pressure) {
  const auto& g = c.grains;
  const auto& k = g.contact;
  // every number with 17 digits except the pressure: two runs of one case give one key, and a
  // pressure typed as 2000 or 2000.0000001 names the same cell
  const std::string text = fmt::format(
      "d {:.17g} poly {:.17g} rho {:.17g} mu {:.17g} law {} kn {:.17g} kt {:.17g} gn {:.17g} "
      "gt {:.17g} E {:.17g} nu {:.17g} e {:.17g} dt {:.17g} P {:.6g}",
      g.diameter, g.polydispersity, g.density, g.friction, k.law, k.kn, k.kt, k.gamma_n,
      k.gamma_t, k.youngs_modulus, k.poisson_ratio, k.restitution, c.dem.dt, pressure);
  return fnv1a64_hex(text);
}

std::string rheology_cache_path(const Case& c, double pressure) {
  const std::string dir = cache_folder(c.dem.packing_cache, "rheology");
  if (dir.empty()) return {};
  return dir + "/rheology-" + grain_material_key(c, pressure) + ".toml";
}

namespace {
/// A clause when the law's points leave the rise of mu(I) undetermined (one-sigma error of
/// mu_2 above mu_2 - mu_s, or of I0 above I0): above the points' largest I the law is then an
/// extrapolation, on which a flow sheared faster (a spinning intruder's wall) depends.
std::string extrapolation_clause(const RheologyFile& law) {
  const MuIFit& m = law.mu_i;
  if (!(m.mu_2_err > std::abs(m.mu_2 - m.mu_s)) && !(m.I0_err > m.I0)) return {};
  return fmt::format(
      "; its points (I up to {:.3g}) leave mu_2 and I0 undetermined (+- {:.2g}, +- {:.2g}): "
      "above that I the law is an extrapolation, which a faster flow (a spinning intruder's "
      "wall) depends on; calibrate up to the flow's I (--inertial-numbers, --strain-scale; "
      "docs/crosscheck.md)",
      law.I_max, m.mu_2_err, m.I0_err);
}
}  // namespace

std::string use_cached_rheology(Case& c) {
  auto& cn = c.continuum;
  if (cn.law_source != "default") return {};
  const double p = c.continuum_pressure();
  if (!(p > 0)) return {};  // no pressure, no continuum run: the FEM says why
  const std::string path = rheology_cache_path(c, p);
  const std::string jop = fmt::format(
      "continuum: mu(I) of Jop et al. 2006 (glass beads: mu_s {}, mu_2 {}, I0 {}), not of "
      "these grains: ",
      cn.mu_s, cn.mu_2, cn.I0);
  if (path.empty() || !std::filesystem::exists(path))
    return fmt::format("{}no calibration is cached for them at {:g} Pa; `grainlift calibrate "
                       "{}` makes one",
                       jop, p, c.source.path);
  RheologyFile law;
  if (const std::string fault = read_cache_entry(path, law); !fault.empty()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    return fmt::format("warning: the cached calibration {} is damaged ({}): {}; {}the cache "
                       "entry for {:g} Pa {}; `grainlift calibrate {}` makes it again",
                       path, fault, ec ? "it could not be removed" : "removed", jop, p,
                       ec ? "is skipped" : "is gone", c.source.path);
  }
  cn.mu_s = law.mu_i.mu_s;
  cn.mu_2 = law.mu_i.mu_2;
  cn.I0 = law.mu_i.I0;
  take_phi_i(law, cn);
  cn.rheology_file = path;
  cn.law_source = "calibration cache";
  return fmt::format("continuum: mu(I) calibrated for these grains at {:g} Pa (mu_s {:.4g}, "
                     "mu_2 {:.4g}, I0 {:.4g}; cached {}); name continuum.mu_s, mu_2, I0 in the "
                     "case to use another law{}",
                     p, cn.mu_s, cn.mu_2, cn.I0, path, extrapolation_clause(law));
}

void cache_rheology(const std::string& path, const RheologyFile& law) {
  const std::string text = rheology_file_text(law, path);
  write_text_atomically(path, text + fmt::format("{}{}\n", kCacheLine, fnv1a64_hex(text)));
}

}  // namespace grainlift
