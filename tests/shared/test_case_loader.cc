// Case parsing and validation: every kind of error names the file, the line and the accepted
// range; --set overrides win over the file, the last one wins, and are validated the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "grainlift/shared/case/case_keys.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "grainlift/shared/rheology/rheology_fit.h"

using namespace grainlift;

namespace {

// A minimal valid case: Kumar's geometry reduced; line numbers below refer to this text.
const std::string base = R"(# test case
[domain]
x_range = [-0.6, 0.6]
y_range = [-0.4, 0.4]
periodic = [true, false]
walls = ["bottom", "top"]

[intruder]
diameter = 0.1
velocity = [1.0, 0.0]
omega = 40.0

[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.8
friction = 0.5
)";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse_case(text, "case.toml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(CaseLoader, ValidCaseFillsDefaultsAndDerivedQuantities) {
  const Case c = parse_case(base, "case.toml");
  EXPECT_DOUBLE_EQ(c.intruder.diameter, 0.1);
  EXPECT_DOUBLE_EQ(c.intruder.velocity[0], 1.0);
  EXPECT_TRUE(c.domain.wall_bottom && c.domain.wall_top);
  EXPECT_FALSE(c.domain.wall_left);
  // Defaults from the registry: Kumar Table I and Guillard's kernel width.
  EXPECT_EQ(c.grains.contact.law, "kumar2019");
  EXPECT_DOUBLE_EQ(c.grains.contact.kt, 2.45e9);
  EXPECT_DOUBLE_EQ(c.dem.dt, 2e-6);
  EXPECT_DOUBLE_EQ(c.output.kernel_width_deg, 8.0);
  EXPECT_EQ(c.output.angles, 64);
  // intruder.friction defaults to grains.friction, continuum.wall_friction to intruder.friction
  EXPECT_DOUBLE_EQ(c.intruder.friction, 0.5);
  EXPECT_DOUBLE_EQ(c.continuum.wall_friction, 0.5);
  // Omega = omega R / V = 40 * 0.05 / 1 = 2 (Kumar eq. 4), exact in floating point to 1e-12
  EXPECT_NEAR(c.spin_ratio(), 2.0, 1e-12);
  // rho = Phi rho_s = 16 kg/m^3 (per unit length)
  EXPECT_NEAR(c.bulk_density(), 16.0, 1e-12);
  EXPECT_EQ(c.source.hash.size(), 16u);
}

// The continuum's default is a stated error, not a level: a case naming neither gets 1% over
// nested levels up to refinement 4; a level stated alone is that level with no target; a target
// alone refines up to 4; without nested levels to stop (nested = false, adaptive cycles) the
// unstated level is 2 and there is no target (the validation refuses a target there).
TEST(CaseLoader, ContinuumDefaultIsATargetErrorNotALevel) {
  auto cn = [](std::vector<std::string> sets) {
    return parse_case(base, "case.toml", std::move(sets)).continuum;
  };
  EXPECT_EQ(cn({}).target_error, 0.01);
  EXPECT_EQ(cn({}).refinement, 4);
  EXPECT_EQ(cn({"continuum.refinement=3"}).target_error, 0.0);
  EXPECT_EQ(cn({"continuum.refinement=3"}).refinement, 3);
  EXPECT_EQ(cn({"continuum.target_error=0.002"}).target_error, 0.002);
  EXPECT_EQ(cn({"continuum.target_error=0.002"}).refinement, 4);
  EXPECT_EQ(cn({"continuum.refinement=5", "continuum.target_error=0.05"}).refinement, 5);
  EXPECT_EQ(cn({"continuum.refinement=5", "continuum.target_error=0.05"}).target_error, 0.05);
  EXPECT_EQ(cn({"continuum.nested=false"}).target_error, 0.0);
  EXPECT_EQ(cn({"continuum.nested=false"}).refinement, 2);
  EXPECT_EQ(cn({"continuum.adaptive_cycles=1"}).target_error, 0.0);
  EXPECT_EQ(cn({"continuum.adaptive_cycles=1"}).refinement, 2);
}

TEST(CaseLoader, LithostaticCentrePressure) {
  // rho g depth: rho = 0.8 * 20 = 16, g = 10, depth = 0.4 - 0.1 = 0.3 -> 48 Pa; the
  // continuum adds its ambient pressure on top.
  const Case c = parse_case(base + "[scene]\ngravity = [0.0, -10.0]\n[continuum]\n"
                            "ambient_pressure = 2.0\n",
                            "case.toml", {"intruder.position=[0.0, 0.1]"});
  EXPECT_NEAR(c.lithostatic_pressure(), 16 * 10 * 0.3, 1e-9);
  EXPECT_NEAR(c.continuum_pressure(), 2.0 + 16 * 10 * 0.3, 1e-9);
}

TEST(CaseLoader, UnknownKeyNamesFileLineAndKey) {
  std::string text = base;
  text.insert(text.find("omega"), "spinn = 3.0\n");  // line 11
  const std::string e = error_of(text);
  EXPECT_TRUE(contains(e, "case.toml:11:")) << e;
  EXPECT_TRUE(contains(e, "unknown key 'intruder.spinn'")) << e;
}

TEST(CaseLoader, UnknownSectionIsAnError) {
  const std::string e = error_of(base + "[granular]\nx = 1\n");
  EXPECT_TRUE(contains(e, "unknown section [granular]")) << e;
  EXPECT_TRUE(contains(e, "case.toml:18:")) << e;
}

TEST(CaseLoader, MissingRequiredKeyIsNamedWithItsUnit) {
  std::string text = base;
  text.erase(text.find("diameter = 0.1\n"), std::string("diameter = 0.1\n").size());
  const std::string e = error_of(text);
  EXPECT_TRUE(contains(e, "missing required key 'intruder.diameter'")) << e;
  EXPECT_TRUE(contains(e, "in m")) << e;
}

TEST(CaseLoader, WrongTypeNamesLineAndExpectedType) {
  std::string text = base;
  text.replace(text.find("omega = 40.0"), 12, "omega = \"fast\"");
  const std::string e = error_of(text);
  EXPECT_TRUE(contains(e, "case.toml:11:")) << e;
  EXPECT_TRUE(contains(e, "'intruder.omega' must be number")) << e;
}

TEST(CaseLoader, OutOfRangeNamesAcceptedRange) {
  std::string text = base;
  text.replace(text.find("area_fraction = 0.8"), 19, "area_fraction = 1.2");
  const std::string e = error_of(text);
  EXPECT_TRUE(contains(e, "case.toml:16:")) << e;
  EXPECT_TRUE(contains(e, "'grains.area_fraction' = 1.2 is out of range")) << e;
  EXPECT_TRUE(contains(e, "accepted: (0, 0.9]")) << e;
}

TEST(CaseLoader, ChoiceOutsideListNamesTheChoices) {
  const std::string e = error_of(base + "[grains.contact]\nlaw = \"hooke\"\n");
  EXPECT_TRUE(contains(e, "one of: kumar2019, guillard2014")) << e;
}

TEST(CaseLoader, ContactKeyOfTheOtherLawIsRefused) {
  const std::string e =
      error_of(base + "[grains.contact]\nlaw = \"guillard2014\"\nkn = 1e9\n");
  EXPECT_TRUE(contains(e, "belongs to law \"kumar2019\"")) << e;
  EXPECT_TRUE(contains(e, "case.toml:20:")) << e;
}

TEST(CaseLoader, CrossChecksGeometryAndRun) {
  // wall on a periodic direction
  std::string e = error_of(base, {"domain.periodic=[true, true]"});
  EXPECT_TRUE(contains(e, "walls 'bottom'/'top' need domain.periodic[1] = false")) << e;
  // intruder outside the box
  e = error_of(base, {"intruder.position=[0.0, 0.39]"});
  EXPECT_TRUE(contains(e, "must lie inside the box")) << e;
  // zero velocity
  e = error_of(base, {"intruder.velocity=[0.0, 0.0]"});
  EXPECT_TRUE(contains(e, "must not be zero")) << e;
  // averaging must start before the end
  e = error_of(base, {"dem.travel=20.0", "dem.steady_travel=30.0"});
  EXPECT_TRUE(contains(e, "must be less than dem.travel")) << e;
  // a pressure lid needs the top wall (it becomes the lid), named with the key's line
  std::string no_top = base;
  const std::string walls = "walls = [\"bottom\", \"top\"]\n";
  no_top.replace(no_top.find(walls), walls.size(), "walls = [\"bottom\"]\nlid_pressure = 100.0\n");
  e = error_of(no_top);
  EXPECT_TRUE(contains(e, "case.toml:7: domain.lid_pressure = 100 Pa needs the \"top\" wall")) << e;
  // the co-moving window left the engine (it failed its validation): its key says so
  e = error_of(base, {"dem.window_width=10.0"});
  EXPECT_TRUE(contains(e, "the co-moving window was removed")) << e;
  EXPECT_TRUE(contains(e, "studies/comoving_window/README.md")) << e;
  e = error_of(base, {"domain.lid_pressure=-1.0"});
  EXPECT_TRUE(contains(e, "'domain.lid_pressure' = -1 is out of range (accepted: [0, 1e+09] Pa)"))
      << e;
  // the continuum's box: a periodic far field needs a periodic x; its top edge (where the DEM's
  // bed settled) must lie between the intruder's top and the top of the box
  e = error_of(base, {"domain.periodic=[false, false]", "continuum.far_field=\"periodic\""});
  EXPECT_TRUE(contains(e, "continuum.far_field = \"periodic\" needs a box periodic in x")) << e;
  e = error_of(base, {"continuum.bed_top=0.5"});
  EXPECT_TRUE(contains(e, "continuum.bed_top = 0.5 m must lie above the intruder's top")) << e;
  EXPECT_EQ(grainlift::parse_case(base, "case.toml", {"continuum.bed_top=0.3"}).continuum.bed_top,
            0.3);
  EXPECT_TRUE(std::isnan(grainlift::parse_case(base, "case.toml", {}).continuum.bed_top));
}

// Physics: none; a lid pressure on a case with the top wall is accepted and read in Pa, and it
// is the confining pressure of both solvers: the continuum's P0 equals it (to the last bit: a
// sum with zeros) and the pressures are matched.
TEST(CaseLoader, LidPressureIsRead) {
  const auto c = grainlift::parse_case(base, "case.toml", {"domain.lid_pressure=1.2066"});
  EXPECT_DOUBLE_EQ(c.domain.lid_pressure, 1.2066);
  EXPECT_EQ(c.continuum_pressure(), 1.2066);
  EXPECT_TRUE(c.pressure_matched());
  // without a lid or gravity the continuum's P0 is only stated, not the DEM bed's
  const auto u = grainlift::parse_case(base, "case.toml", {"continuum.ambient_pressure=500"});
  EXPECT_EQ(u.continuum_pressure(), 500.0);
  EXPECT_FALSE(u.pressure_matched());
}

// A lid and a continuum ambient pressure together would give the two solvers two pressures:
// refused, naming the line of the ambient pressure (after the lid override) and the remedy.
TEST(CaseLoader, LidAndAmbientPressureTogetherAreRefused) {
  const std::string e = error_of(base + "[continuum]\nambient_pressure = 2.0\n",
                                 {"domain.lid_pressure=1.0"});
  EXPECT_TRUE(contains(e, "case.toml:19: continuum.ambient_pressure = 2 Pa and "
                          "domain.lid_pressure = 1 Pa")) << e;
  EXPECT_TRUE(contains(e, "remove continuum.ambient_pressure")) << e;
}

TEST(CaseLoader, InvalidTomlNamesLineAndColumn) {
  const std::string e = error_of(base + "[dem\n");
  EXPECT_TRUE(contains(e, "case.toml:18:")) << e;
  EXPECT_TRUE(contains(e, "invalid TOML")) << e;
}

TEST(CaseLoader, AllErrorsAreReportedTogether) {
  std::string text = base;
  text.replace(text.find("area_fraction = 0.8"), 19, "area_fraction = 1.2");
  text.replace(text.find("friction = 0.5"), 14, "friction = -1.0");
  const std::string e = error_of(text);
  EXPECT_TRUE(contains(e, "grains.area_fraction")) << e;
  EXPECT_TRUE(contains(e, "grains.friction")) << e;
}

TEST(CaseLoader, OverridesWinOverTheFileAndTheLastOneWins) {
  const Case c = parse_case(base, "case.toml",
                            {"grains.friction=0.3", "intruder.omega=10", "intruder.omega=20.0"});
  EXPECT_DOUBLE_EQ(c.grains.friction, 0.3);
  EXPECT_DOUBLE_EQ(c.intruder.omega, 20.0);  // last --set wins; an integer is accepted as real
  // the defaulted friction of the intruder follows the overridden grain friction
  EXPECT_DOUBLE_EQ(c.intruder.friction, 0.3);
  // overrides can add keys and sub-tables the file does not have; bare words are strings
  const Case d = parse_case(base, "case.toml", {"grains.contact.law=guillard2014",
                                                 "grains.contact.restitution=0.7"});
  EXPECT_EQ(d.grains.contact.law, "guillard2014");
  EXPECT_DOUBLE_EQ(d.grains.contact.restitution, 0.7);
  // the case hash records the overrides
  EXPECT_NE(parse_case(base, "case.toml").source.hash, c.source.hash);
  EXPECT_EQ(c.source.overrides.size(), 3u);
}

TEST(CaseLoader, OverridesAreValidatedAndNamedInErrors) {
  std::string e = error_of(base, {"grains.friction=-2"});
  EXPECT_TRUE(contains(e, "--set 'grains.friction=-2'")) << e;
  EXPECT_TRUE(contains(e, "accepted: [0, 10]")) << e;
  e = error_of(base, {"grains.fricton=0.2"});
  EXPECT_TRUE(contains(e, "unknown key 'grains.fricton'")) << e;
  e = error_of(base, {"nonsense"});
  EXPECT_TRUE(contains(e, "expected section.key=value")) << e;
}

TEST(CaseLoader, UnreadableFileIsAnInputError) {
  EXPECT_THROW(load_case("/nonexistent/case.toml"), InputError);
}

TEST(CaseLoader, EveryShippedCaseValidates) {
  // Physics: none; every case folder the project ships must hold valid cases and a README; its
  // calibrated rheology files (rheology*.toml, named by a case) must read as rheology files.
  int cases = 0;
  for (const auto& dir : std::filesystem::directory_iterator(GRAINLIFT_SOURCE_DIR "/cases")) {
    if (!dir.is_directory()) continue;
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "README.md")) << dir.path();
    for (const auto& f : std::filesystem::directory_iterator(dir.path()))
      if (f.path().extension() != ".toml") continue;
      else if (f.path().filename().string().rfind("rheology", 0) == 0)
        EXPECT_NO_THROW(read_rheology_file(f.path().string())) << f.path();
      else {
        EXPECT_NO_THROW(load_case(f.path().string())) << f.path();
        ++cases;
      }
  }
  EXPECT_GE(cases, 3);
}

TEST(CaseKeys, DocsListEveryKey) {
  // docs/case-format.md embeds the registry table; a key added without docs fails here.
  std::ifstream in(GRAINLIFT_SOURCE_DIR "/docs/case-format.md");
  ASSERT_TRUE(in) << "docs/case-format.md missing";
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(doc, keys_markdown()))
      << "regenerate the table with `build/bin/grainlift keys --markdown`";
}

// A case that names a calibrated rheology file (relative to its own folder) gets the file's
// mu_s, mu_2, I0 exactly, in place of the continuum keys; naming the file and one of those keys
// too is refused with the key's line; a missing file is refused naming it.
TEST(CaseLoader, RheologyFileReplacesTheContinuumLaw) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("grainlift_rheology_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<grainlift::ShearPoint> pts;
  for (int k = 0; k < 8; ++k) {
    const double I = 1e-3 * std::pow(2.4, k);
    pts.push_back({I, grainlift::jop_mu(I, 0.26, 0.8, 0.3), 0.005, 0.81 - 0.3 * I, 0.002});
  }
  const grainlift::RheologyFile law = grainlift::make_rheology_file(pts, {{"grains", "test"}});
  grainlift::write_rheology_file((dir / "law.toml").string(), law);
  const std::string case_path = (dir / "case.toml").string();
  const grainlift::Case c = grainlift::parse_case(
      base + "[continuum]\nrheology_file = \"law.toml\"\n", case_path);
  EXPECT_EQ(c.continuum.mu_s, law.mu_i.mu_s);
  EXPECT_EQ(c.continuum.mu_2, law.mu_i.mu_2);
  EXPECT_EQ(c.continuum.I0, law.mu_i.I0);
  EXPECT_NEAR(c.continuum.mu_s, 0.26, 1e-6);  // the fit of exact points gives the law back
  EXPECT_EQ(c.continuum.rheology_file, (dir / "law.toml").string());
  std::string e;
  try {
    grainlift::parse_case(base + "[continuum]\nrheology_file = \"law.toml\"\nmu_s = 0.3\n",
                          case_path);
  } catch (const grainlift::InputError& x) {
    e = x.what();
  }
  EXPECT_TRUE(contains(e, "case.toml:20: continuum.mu_s and continuum.rheology_file both give "
                          "mu(I)")) << e;
  e.clear();
  try {
    grainlift::parse_case(base + "[continuum]\nrheology_file = \"missing.toml\"\n", case_path);
  } catch (const grainlift::InputError& x) {
    e = x.what();
  }
  EXPECT_TRUE(contains(e, "missing.toml")) << e;
  fs::remove_all(dir);
}

namespace {
/// A calibrated law from 8 exact points of Jop's mu(I) (mu_s 0.26, mu_2 0.8, I0 0.3: frictional
/// disks) and Phi = 0.81 - 0.3 I, I from 1e-3 to 0.46: a rheology file to add tables to.
grainlift::RheologyFile frictional_disks_law() {
  std::vector<grainlift::ShearPoint> pts;
  for (int k = 0; k < 8; ++k) {
    const double I = 1e-3 * std::pow(2.4, k);
    pts.push_back({I, grainlift::jop_mu(I, 0.26, 0.8, 0.3), 0.005, 0.81 - 0.3 * I, 0.002});
  }
  return grainlift::make_rheology_file(pts, {{"grains", "test"}});
}
}  // namespace

// continuum.wall_law: "coulomb" by default (the wall's friction is continuum.wall_friction,
// default intruder.friction = grains.friction 0.5: today's results); "measured" takes the
// friction of the rheology file's [wall] table exactly, "measured_slip" its slip law (mu_a,
// mu_b, v0 exactly; v0 = 0, no law, otherwise); both are refused with a line that says
// why without a rheology file, with a file that has no [wall], beside continuum.wall_friction,
// or on a no-slip wall.
TEST(CaseLoader, MeasuredWallLawTakesTheRheologyFilesWallFriction) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("grainlift_wall_law_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  grainlift::RheologyFile law = frictional_disks_law();
  grainlift::write_rheology_file((dir / "plain.toml").string(), law);
  grainlift::WallLaw w;
  w.friction = 0.205;
  w.friction_err = 0.038;
  w.mu_a = 0.03;
  w.mu_a_err = 0.01;
  w.mu_b = 0.33;
  w.mu_b_err = 0.03;
  w.v0 = 0.079;
  w.v0_err = 0.01;
  w.chi2_per_dof = 0.78;
  w.points = 142;
  law.wall = w;
  grainlift::write_rheology_file((dir / "wall.toml").string(), law);
  const std::string case_path = (dir / "case.toml").string();
  const std::string coulomb = base + "[continuum]\nwall = \"coulomb\"\n";

  const grainlift::Case d = grainlift::parse_case(coulomb, case_path);
  EXPECT_EQ(d.continuum.wall_law, "coulomb");
  EXPECT_EQ(d.continuum.wall_friction, 0.5);
  const grainlift::Case m = grainlift::parse_case(
      coulomb + "rheology_file = \"wall.toml\"\nwall_law = \"measured\"\n", case_path);
  EXPECT_EQ(m.continuum.wall_law, "measured");
  EXPECT_EQ(m.continuum.wall_friction, 0.205);
  EXPECT_EQ(m.continuum.mu_s, law.mu_i.mu_s);
  EXPECT_EQ(m.continuum.wall_v0, 0.0);  // constant: no slip law
  const grainlift::Case ms = grainlift::parse_case(
      coulomb + "rheology_file = \"wall.toml\"\nwall_law = \"measured_slip\"\n", case_path);
  EXPECT_EQ(ms.continuum.wall_mu_a, 0.03);
  EXPECT_EQ(ms.continuum.wall_mu_b, 0.33);
  EXPECT_EQ(ms.continuum.wall_v0, 0.079);
  EXPECT_EQ(d.continuum.wall_v0, 0.0);
  // the same through --set
  const grainlift::Case s = grainlift::parse_case(
      coulomb + "rheology_file = \"wall.toml\"\n", case_path,
      {"continuum.wall_law=\"measured\""});
  EXPECT_EQ(s.continuum.wall_friction, 0.205);

  auto error = [&](const std::string& text) {
    try {
      grainlift::parse_case(text, case_path);
    } catch (const grainlift::InputError& x) {
      return std::string(x.what());
    }
    return std::string();
  };
  std::string e = error(coulomb + "wall_law = \"measured\"\n");
  EXPECT_TRUE(contains(e, "case.toml:20: continuum.wall_law = \"measured\" reads the [wall] "
                          "table of continuum.rheology_file")) << e;
  e = error(coulomb + "rheology_file = \"plain.toml\"\nwall_law = \"measured\"\n");
  EXPECT_TRUE(contains(e, "plain.toml has no [wall] table")) << e;
  e = error(coulomb + "rheology_file = \"wall.toml\"\nwall_law = \"measured\"\n"
                      "wall_friction = 0.3\n");
  EXPECT_TRUE(contains(e, "case.toml:22: continuum.wall_friction and continuum.wall_law")) << e;
  e = error(base + "[continuum]\nrheology_file = \"wall.toml\"\nwall_law = \"measured\"\n");
  EXPECT_TRUE(contains(e, "needs continuum.wall = \"coulomb\"")) << e;
  e = error(coulomb + "wall_law = \"calibrated\"\n");
  EXPECT_TRUE(contains(e, "coulomb") && contains(e, "measured")) << e;
  fs::remove_all(dir);
}

// continuum.nonlocal_amplitude: the nonlocal fluidity's A is the case's when stated (or its
// default 0.5 without a [nonlocal] table: today's runs), else the A the rheology file's
// [nonlocal] table measured (grainlift calibrate --nonlocal), taken exactly and named as the
// source; the table reads back as written and an amplitude <= 0 is refused naming the key.
TEST(CaseLoader, NonlocalAmplitudeComesFromTheRheologyFileUnlessStated) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("grainlift_nonlocal_a_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  grainlift::RheologyFile law = frictional_disks_law();
  grainlift::write_rheology_file((dir / "plain.toml").string(), law);
  law.nonlocal = grainlift::Cooperativity{0.731, 0.12, 1.4, 9, 0.15, 0.22};
  const std::string with_a = (dir / "nonlocal.toml").string();
  grainlift::write_rheology_file(with_a, law);
  const grainlift::RheologyFile back = grainlift::read_rheology_file(with_a);
  ASSERT_TRUE(back.nonlocal.has_value());
  EXPECT_EQ(back.nonlocal->amplitude, 0.731);
  EXPECT_EQ(back.nonlocal->amplitude_err, 0.12);
  EXPECT_EQ(back.nonlocal->points, 9);
  EXPECT_EQ(back.nonlocal->mu_max, 0.22);
  const std::string case_path = (dir / "case.toml").string();
  const std::string ngf = base + "[continuum]\nmodel = \"nonlocal_fluidity\"\n";
  const grainlift::Case plain =
      grainlift::parse_case(ngf + "rheology_file = \"plain.toml\"\n", case_path);
  EXPECT_EQ(plain.continuum.nonlocal_amplitude, 0.5);
  EXPECT_EQ(plain.continuum.nonlocal_amplitude_source, "continuum.nonlocal_amplitude");
  const grainlift::Case measured =
      grainlift::parse_case(ngf + "rheology_file = \"nonlocal.toml\"\n", case_path);
  EXPECT_EQ(measured.continuum.nonlocal_amplitude, 0.731);
  EXPECT_TRUE(contains(measured.continuum.nonlocal_amplitude_source, "[nonlocal] of"));
  const grainlift::Case stated = grainlift::parse_case(
      ngf + "rheology_file = \"nonlocal.toml\"\nnonlocal_amplitude = 0.2\n", case_path);
  EXPECT_EQ(stated.continuum.nonlocal_amplitude, 0.2);
  std::string text;
  {
    std::ifstream in(with_a);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string bad = (dir / "bad.toml").string();
  std::ofstream(bad) << text.replace(text.find("amplitude = "), 17, "amplitude = -0.1\n#");
  try {
    grainlift::read_rheology_file(bad);
    ADD_FAILURE() << "an amplitude of -0.1 was accepted";
  } catch (const grainlift::InputError& e) {
    EXPECT_TRUE(contains(e.what(), "[nonlocal] amplitude = -0.1")) << e.what();
  }
  fs::remove_all(dir);
}

// Guillard et al. (2014), Sec. II: three ways of putting the intruder at depth h. All three
// give the same confining pressure P0 = rho g h at the centre (rho = Phi rho_s); the free surface
// and the heavy lid with the gradient rho g, the lid alone without it. The equivalent depth of
// the heavy lid in 2D is h = (ymax - y_c) + P_lid / (rho g). Exact arithmetic: 1e-12 relative.
TEST(CaseLoader, DepthModesDeriveLidBoxAndGravityFromTheDepth) {
  const double rho = 0.8 * 20.0, g = 9.81, h = 0.9;
  const std::vector<std::string> grav = {"scene.gravity=[0.0, -9.81]", "scene.depth=0.9"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> s = grav;
    s.insert(s.end(), extra.begin(), extra.end());
    return s;
  };
  const Case heavy = parse_case(base, "case.toml", with({"scene.depth_mode=\"heavy_lid\""}));
  EXPECT_NEAR(heavy.domain.lid_pressure, rho * g * (h - 0.4), 1e-12 * rho * g * h);
  EXPECT_NEAR(heavy.stated_pressure(), rho * g * h, 1e-12 * rho * g * h);
  EXPECT_NEAR(heavy.equivalent_depth(), h, 1e-12 * h);
  EXPECT_DOUBLE_EQ(heavy.scene.gravity[1], -g);

  const Case lid = parse_case(base, "case.toml", with({"scene.depth_mode=\"lid_only\""}));
  EXPECT_NEAR(lid.domain.lid_pressure, rho * g * h, 1e-12 * rho * g * h);
  EXPECT_EQ(lid.scene.gravity[0], 0.0);
  EXPECT_EQ(lid.scene.gravity[1], 0.0);  // the grains feel no gravity: no gradient
  EXPECT_DOUBLE_EQ(lid.reference_gravity(), g);
  EXPECT_NEAR(lid.equivalent_depth(), h, 1e-12 * h);

  const Case free = parse_case(
      base, "case.toml", with({"scene.depth_mode=\"free_surface\"", "domain.walls=[\"bottom\"]"}));
  EXPECT_NEAR(free.domain.y_range[1], h, 1e-12);  // intruder at y = 0: the top is at h
  EXPECT_EQ(free.domain.lid_pressure, 0.0);
  EXPECT_NEAR(free.stated_pressure(), rho * g * h, 1e-12 * rho * g * h);
}

// Depth modes refuse what would make a different depth than the one stated, naming the key.
TEST(CaseLoader, DepthModesRefuseContradictions) {
  const std::string g = "scene.gravity=[0.0, -9.81]";
  EXPECT_TRUE(contains(error_of(base, {"scene.depth=0.5"}), "needs scene.depth_mode"));
  EXPECT_TRUE(contains(error_of(base, {"scene.depth_mode=\"heavy_lid\"", g}), "scene.depth > 0"));
  EXPECT_TRUE(contains(error_of(base, {"scene.depth_mode=\"heavy_lid\"", "scene.depth=0.9"}),
                       "gravity along -y"));
  // the real bed above the centre (0.4 m) is deeper than the stated depth
  EXPECT_TRUE(contains(error_of(base, {"scene.depth_mode=\"heavy_lid\"", g, "scene.depth=0.3"}),
                       "must exceed the real depth"));
  EXPECT_TRUE(contains(error_of(base, {"scene.depth_mode=\"free_surface\"", g, "scene.depth=0.3"}),
                       "no top wall"));
  EXPECT_TRUE(contains(error_of(base, {"scene.depth_mode=\"lid_only\"", g, "scene.depth=0.3",
                                       "domain.lid_pressure=2.0"}),
                       "remove it"));
  std::string no_top = base;
  no_top.replace(no_top.find("walls = [\"bottom\", \"top\"]"), 26, "walls = [\"bottom\"]");
  const std::string e = error_of(no_top, {"scene.depth_mode=\"lid_only\"", g, "scene.depth=0.3"});
  EXPECT_TRUE(contains(e, "case.toml:6")) << e;  // the line of domain.walls
  EXPECT_TRUE(contains(e, "needs the \"top\" wall")) << e;
}
