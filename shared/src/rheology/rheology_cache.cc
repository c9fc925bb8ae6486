#include "grainlift/shared/rheology/rheology_cache.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

#include "grainlift/shared/rheology/rheology_file.h"

namespace grainlift {

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
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a 64
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

std::string rheology_cache_path(const Case& c, double pressure) {
  const std::string dir = cache_folder(c.dem.packing_cache, "rheology");
  if (dir.empty()) return {};
  return dir + "/rheology-" + grain_material_key(c, pressure) + ".toml";
}

std::string use_cached_rheology(Case& c) {
  auto& cn = c.continuum;
  if (cn.law_source != "default") return {};
  const double p = c.continuum_pressure();
  if (!(p > 0)) return {};  // no pressure, no continuum run: the FEM says why
  const std::string path = rheology_cache_path(c, p);
  if (path.empty() || !std::filesystem::exists(path))
    return fmt::format(
        "continuum: mu(I) of Jop et al. 2006 (glass beads: mu_s {}, mu_2 {}, I0 {}), not of "
        "these grains: no calibration is cached for them at {:g} Pa; `grainlift calibrate {}` "
        "makes one",
        cn.mu_s, cn.mu_2, cn.I0, p, c.source.path);
  const RheologyFile law = read_rheology_file(path);
  cn.mu_s = law.mu_i.mu_s;
  cn.mu_2 = law.mu_i.mu_2;
  cn.I0 = law.mu_i.I0;
  cn.rheology_file = path;
  cn.law_source = "calibration cache";
  return fmt::format("continuum: mu(I) calibrated for these grains at {:g} Pa (mu_s {:.4g}, "
                     "mu_2 {:.4g}, I0 {:.4g}; cached {}); name continuum.mu_s, mu_2, I0 in the "
                     "case to use another law",
                     p, cn.mu_s, cn.mu_2, cn.I0, path);
}

}  // namespace grainlift
