// The calibration cache (rheology_cache.h): a calibrated law is found again only for the same
// grains at the same pressure, and a run whose case states no law of its own takes it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "grainlift/shared/rheology/rheology_fit.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

// Kumar's grains under a lid at P0 = 2000 Pa; [dem] packing_cache is appended per test.
const std::string base = R"([domain]
x_range = [-0.4, 0.4]
y_range = [-0.24, 0.24]
periodic = [true, false]
walls = ["bottom", "top"]
lid_pressure = 2000.0

[intruder]
diameter = 0.1
velocity = [0.5, 0.0]

[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.8
friction = 0.5
)";

fs::path scratch(const std::string& tag) {
  const fs::path d = fs::temp_directory_path() /
                     ("grainlift_rheology_cache_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Case with_cache(const fs::path& dir, const std::string& extra = "",
                const std::vector<std::string>& sets = {}) {
  return parse_case(base + extra + "\n[dem]\npacking_cache = \"" + dir.string() + "\"\n",
                    "case.toml", sets);
}

/// A rheology file of Jop's law with mu_s 0.24, mu_2 0.88, I0 0.7, fitted to exact points.
RheologyFile synthetic_law() {
  std::vector<ShearPoint> pts;
  for (int k = 0; k < 8; ++k) {
    const double I = 1e-3 * std::pow(2.4, k);
    pts.push_back({I, jop_mu(I, 0.24, 0.88, 0.7), 0.005, 0.79 - 0.3 * I, 0.002});
  }
  return make_rheology_file(pts, {{"grains", "test"}});
}

}  // namespace

// The shear cell's mu(I) depends on the grains' size distribution, density, friction, contact
// law and its parameters, the time step and the confining pressure (through the stiffness
// number kn d / P): changing any one of them must not find another material's calibration.
// The same case gives the same key, and a pressure that differs in the 9th digit is the same
// cell (the key keeps 6).
TEST(RheologyCache, KeyNamesTheMaterialAndThePressure) {
  const fs::path dir = scratch("key");
  const Case c = with_cache(dir);
  const std::string key = grain_material_key(c, 2000);
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(grain_material_key(with_cache(dir), 2000), key);
  EXPECT_EQ(grain_material_key(c, 2000.0000001), key);
  EXPECT_NE(grain_material_key(c, 2100), key);
  for (const std::string set :
       {"grains.diameter=0.021", "grains.polydispersity=0.2", "grains.density=21.0",
        "grains.friction=0.4", "grains.contact.kn=3e9", "dem.dt=1e-6"})
    EXPECT_NE(grain_material_key(with_cache(dir, "", {set}), 2000), key) << set;
  // the intruder and the box are not the material
  EXPECT_EQ(grain_material_key(with_cache(dir, "", {"intruder.omega=5.0"}), 2000), key);
  EXPECT_EQ(rheology_cache_path(c, 2000), dir.string() + "/rheology/rheology-" + key + ".toml");
  fs::remove_all(dir);
}

// A case that states no mu(I) keeps the registry's default (Jop et al. 2006) while nothing is
// cached, and the note tells the user how to calibrate; once a calibration of its grains at
// its P0 is cached, the continuum takes that file's mu_s, mu_2, I0 exactly. A case that names
// its own law (keys or a rheology file) is never changed, and dem.packing_cache = "" switches
// the cache off.
TEST(RheologyCache, RunsWithoutALawOfTheirOwnTakeTheCachedCalibration) {
  const fs::path dir = scratch("use");
  Case c = with_cache(dir);
  ASSERT_EQ(c.continuum.law_source, "default");
  const double jop_mu_s = c.continuum.mu_s;
  std::string note = use_cached_rheology(c);
  EXPECT_NE(note.find("grainlift calibrate"), std::string::npos) << note;
  EXPECT_EQ(c.continuum.law_source, "default");
  EXPECT_EQ(c.continuum.mu_s, jop_mu_s);

  const RheologyFile law = synthetic_law();
  const std::string cached = rheology_cache_path(c, c.continuum_pressure());
  fs::create_directories(fs::path(cached).parent_path());
  write_rheology_file(cached, law);
  note = use_cached_rheology(c);
  EXPECT_NE(note.find("calibrated for these grains at 2000 Pa"), std::string::npos) << note;
  EXPECT_EQ(c.continuum.law_source, "calibration cache");
  EXPECT_EQ(c.continuum.rheology_file, cached);
  EXPECT_EQ(c.continuum.mu_s, law.mu_i.mu_s);
  EXPECT_EQ(c.continuum.mu_2, law.mu_i.mu_2);
  EXPECT_EQ(c.continuum.I0, law.mu_i.I0);
  EXPECT_NEAR(c.continuum.mu_s, 0.24, 1e-6);
  // its points (to I = 0.46, on both sides of I0 = 0.7 within their errors) determine the law
  EXPECT_EQ(note.find("extrapolation"), std::string::npos) << note;
  // a law whose points leave mu_2 undetermined (the demo's grains cached by 82e36ce: mu_2
  // 2.32 +- 31 from points up to I = 0.23) is taken the same, and the note says that above
  // its points the law is an extrapolation
  RheologyFile loose = law;
  loose.mu_i.mu_2_err = 31;
  write_rheology_file(cached, loose);
  Case again = with_cache(dir);
  note = use_cached_rheology(again);
  EXPECT_EQ(again.continuum.mu_2, law.mu_i.mu_2);
  EXPECT_NE(note.find("is an extrapolation"), std::string::npos) << note;
  EXPECT_NE(note.find("+- 31"), std::string::npos) << note;
  write_rheology_file(cached, law);

  Case stated = with_cache(dir, "\n[continuum]\nmu_s = 0.3\n");
  EXPECT_EQ(stated.continuum.law_source, "case");
  EXPECT_EQ(use_cached_rheology(stated), "");
  EXPECT_EQ(stated.continuum.mu_s, 0.3);

  Case other_pressure = with_cache(dir, "", {"domain.lid_pressure=500.0"});
  use_cached_rheology(other_pressure);
  EXPECT_EQ(other_pressure.continuum.law_source, "default");

  Case off = parse_case(base + "\n[dem]\npacking_cache = \"\"\n", "case.toml");
  use_cached_rheology(off);
  EXPECT_EQ(off.continuum.law_source, "default");
  EXPECT_EQ(off.continuum.mu_s, jop_mu_s);
  fs::remove_all(dir);
}

// A cache entry carries a checksum of its bytes (cache_rheology): one digit changed in it, or
// a file cut short, is found when a run looks for the calibration, reported as a damaged cache
// entry (not as bad input of the case), removed, and the run goes on with the default law as
// if nothing were cached. The sound entry is taken exactly; so is an entry of the format
// before checksums (no checksum line), which still reads.
TEST(RheologyCache, DamagedEntryIsReportedRemovedAndSkipped) {
  const fs::path dir = scratch("damaged");
  const RheologyFile law = synthetic_law();
  Case c = with_cache(dir);
  const double jop_mu_s = c.continuum.mu_s;
  const std::string cached = rheology_cache_path(c, c.continuum_pressure());
  fs::create_directories(fs::path(cached).parent_path());
  cache_rheology(cached, law);
  std::string note = use_cached_rheology(c);
  EXPECT_EQ(c.continuum.law_source, "calibration cache") << note;
  EXPECT_EQ(c.continuum.mu_s, law.mu_i.mu_s);

  auto damage = [&](auto edit) {
    std::ifstream in(cached);
    std::stringstream b;
    b << in.rdbuf();
    std::string text = b.str();
    edit(text);
    std::ofstream(cached, std::ios::trunc) << text;
  };
  // one digit of mu_s changed: still valid TOML and a valid law, but not what was cached
  damage([](std::string& t) {
    const std::size_t at = t.find("mu_s = 0.") + 9;
    t[at] = t[at] == '1' ? '2' : '1';
  });
  Case d = with_cache(dir);
  note = use_cached_rheology(d);
  EXPECT_NE(note.find("is damaged (its checksum does not match)"), std::string::npos) << note;
  EXPECT_NE(note.find("grainlift calibrate"), std::string::npos) << note;
  EXPECT_FALSE(fs::exists(cached));
  EXPECT_EQ(d.continuum.law_source, "default");
  EXPECT_EQ(d.continuum.mu_s, jop_mu_s);

  // cut short: the checksum line is gone and what is left is no rheology file
  cache_rheology(cached, law);
  damage([](std::string& t) { t.resize(t.size() / 3); });
  Case e = with_cache(dir);
  note = use_cached_rheology(e);
  EXPECT_NE(note.find("is damaged"), std::string::npos) << note;
  EXPECT_FALSE(fs::exists(cached));
  EXPECT_EQ(e.continuum.law_source, "default");

  // an entry written before checksums (the plain rheology file) is read as it is
  write_rheology_file(cached, law);
  Case f = with_cache(dir);
  use_cached_rheology(f);
  EXPECT_EQ(f.continuum.law_source, "calibration cache");
  fs::remove_all(dir);
}
