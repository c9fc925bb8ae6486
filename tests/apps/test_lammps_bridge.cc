// The LAMMPS bridge through the real command (docs/lammps.md): `grainlift export lammps` writes
// a case LAMMPS runs, `grainlift import lammps` reads the run back into the schema, and both
// codes, started from the same exported bed, do the same physics. The tests that run LAMMPS
// are skipped, with a message, where `lmp` is not on the PATH (Debian: apt install lammps;
// scripts/install-deps installs it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "grainlift/shared/results/compare.h"
#include "grainlift/shared/results/result_file.h"
#include "run_command.h"
#include "tiny_dem_case.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("grainlift_lammps_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "tiny.toml") << test_support::tiny_case;
  return d;
}

bool have_lammps() { return test_support::run_command("command -v lmp").code == 0; }

// The tiny case without fields (LAMMPS's run has none) and with 30 d of travel.
const std::string kSets = " --set output.fields=false --set dem.travel=30";

/// Exports the tiny case to d/lammps, runs LAMMPS there, imports into d/imported, and runs
/// grainlift's DEM on the same case into d/grainlift.
void run_both(const fs::path& d, const std::string& sets = kSets) {
  const std::string tiny = (d / "tiny.toml").string(), exp = (d / "lammps").string();
  auto o = test_support::run_grainlift("export lammps " + tiny + " " + exp + sets);
  ASSERT_EQ(o.code, 0) << o.output;
  o = test_support::run_command("cd " + exp + " && lmp -in in.grainlift -screen none");
  ASSERT_EQ(o.code, 0) << o.output;
  o = test_support::run_grainlift("import lammps " + exp + " --out " + (d / "imported").string());
  ASSERT_EQ(o.code, 0) << o.output;
  o = test_support::run_grainlift("run " + tiny + " --solver dem --quiet --out " +
                                  (d / "grainlift").string() + sets);
  ASSERT_EQ(o.code, 0) << o.output;
}

}  // namespace

// Same bed, same contact law, same prescribed intruder: until the grains' chaotic dynamics
// part the two runs (after some 0.5 d of travel), the force on the intruder is the same
// sample by sample. What differs by construction is the velocity the damping sees (grainlift:
// synchronised at t + dt; LAMMPS: mid-step), measured at 0.45-0.54% (relative L2 over the
// first 25 samples, 0.1 d of travel, two beds). Asserted below 2%: a stiffness, damping, mass,
// radius, spin sign or time step mapped wrong gives tens of percent.
namespace {
/// Relative L2 difference of the force series of d/imported and d/grainlift over the first
/// @p n samples.
double early_difference(const fs::path& d, std::size_t n) {
  const RunResult a = read_result((d / "imported" / "dem.h5").string());
  const RunResult b = read_result((d / "grainlift" / "dem.h5").string());
  EXPECT_TRUE(a.forces && b.forces);
  if (!a.forces || !b.forces) return NAN;
  EXPECT_EQ(a.forces->time.size(), b.forces->time.size());
  EXPECT_GE(b.forces->time.size(), n);
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < n && i < b.forces->time.size(); ++i) {
    EXPECT_NEAR(a.forces->time[i], b.forces->time[i], 1e-12);
    diff += std::pow(a.forces->fx[i] - b.forces->fx[i], 2) +
            std::pow(a.forces->fy[i] - b.forces->fy[i], 2);
    norm += std::pow(b.forces->fx[i], 2) + std::pow(b.forces->fy[i], 2);
  }
  EXPECT_GT(norm, 0.0) << "no contact with the intruder in the first samples";
  return std::sqrt(diff / norm);
}
}  // namespace

TEST(LammpsBridge, SameBedGivesTheSameForcesUntilTheDynamicsPart) {
  if (!have_lammps()) GTEST_SKIP() << "lmp not found: Debian's lammps package is needed";
  const fs::path d = scratch("early");
  run_both(d);
  EXPECT_LT(early_difference(d, 25), 0.02);
}

// The same with Guillard's law (pair granular: hertz/material, mindlin, tsuji damping handed
// the restitution whose prefactor is Guillard's sqrt(5)|beta|), at 0.5 m/s (at 2 m/s the soft
// grains overlap beyond grainlift's limit): measured 0.87% over the first 50 samples
// (0.05 d of travel), 4% over the first 10 (the first impacts, where damping dominates).
// Asserted below 3% over 50 samples.
TEST(LammpsBridge, GuillardLawGivesTheSameForcesUntilTheDynamicsPart) {
  if (!have_lammps()) GTEST_SKIP() << "lmp not found: Debian's lammps package is needed";
  const fs::path d = scratch("guillard");
  run_both(d, " --set output.fields=false --set grains.contact.law=guillard2014 "
              "--set intruder.velocity=[0.5,0.0] --set intruder.omega=20 --set dem.travel=3");
  EXPECT_LT(early_difference(d, 50), 0.03);
}

// Over the whole run the two codes give mean drag and lift that agree within three combined
// block standard errors (independent Gaussian errors would exceed that 0.3% of the time); the
// imported file has every block the DEM's has except fields, and the dumped contact forces
// (pair/local, re-evaluated with end-of-step velocities) sum to LAMMPS's force on the intruder
// within 5% (measured 0.7% on the dilute reduced Kumar bed).
TEST(LammpsBridge, MeanDragAndLiftAgreeWithinTheirCombinedErrors) {
  if (!have_lammps()) GTEST_SKIP() << "lmp not found: Debian's lammps package is needed";
  const fs::path d = scratch("means");
  run_both(d);
  const RunResult a = read_result((d / "imported" / "dem.h5").string());
  const RunResult b = read_result((d / "grainlift" / "dem.h5").string());
  ASSERT_TRUE(a.means && b.means && a.surface && a.histogram);
  ASSERT_TRUE(a.means->drag_stderr && b.means->drag_stderr && a.means->lift_stderr &&
              b.means->lift_stderr);
  EXPECT_EQ(a.meta.case_hash, b.meta.case_hash);
  EXPECT_EQ(a.means->samples, b.means->samples);
  const double drag_err = std::hypot(*a.means->drag_stderr, *b.means->drag_stderr);
  const double lift_err = std::hypot(*a.means->lift_stderr, *b.means->lift_stderr);
  EXPECT_LT(std::abs(a.means->drag - b.means->drag), 3 * drag_err)
      << "LAMMPS " << a.means->drag << ", grainlift " << b.means->drag;
  EXPECT_LT(std::abs(a.means->lift - b.means->lift), 3 * lift_err)
      << "LAMMPS " << a.means->lift << ", grainlift " << b.means->lift;
  EXPECT_GT(a.means->drag, 0.0);
  ASSERT_TRUE(a.diagnostics.values.count("lammps_contact_force_mismatch"));
  EXPECT_LT(a.diagnostics.values.at("lammps_contact_force_mismatch"), 0.05);
  // compare reads the two files as it reads any pair of results
  const Comparison c = compare_results(b, a);
  ASSERT_TRUE(c.drag_rel.has_value());
  EXPECT_LT(std::abs(*c.drag_rel), 3 * drag_err / b.means->drag);
}

// What LAMMPS cannot express here is refused before anything is written, naming the key.
TEST(LammpsBridge, ExportRefusesALidAndImportRefusesAFolderWithoutARun) {
  const fs::path d = scratch("refuse");
  auto o = test_support::run_grainlift("export lammps " + (d / "tiny.toml").string() + " " +
                                       (d / "lid").string() + " --set domain.lid_pressure=100");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("domain.lid_pressure"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(d / "lid" / "in.grainlift"));
  // an export that LAMMPS never ran: import names the missing file and how to make it
  o = test_support::run_grainlift("export lammps " + (d / "tiny.toml").string() + " " +
                                  (d / "norun").string() + " --set output.fields=false");
  ASSERT_EQ(o.code, 0) << o.output;
  o = test_support::run_grainlift("import lammps " + (d / "norun").string() + " --out " +
                                  (d / "out").string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("forces.txt"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("lmp -in in.grainlift"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(d / "out" / "dem.h5"));
  // a folder that is no export at all
  o = test_support::run_grainlift("import lammps " + d.string() + " --out " + (d / "out").string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("export.txt"), std::string::npos) << o.output;
}

// A LAMMPS run stopped while writing (the last dump block cut short) imports as a partial
// result up to its last complete sample; a malformed line before the end is refused with its
// file and line. LAMMPS's outputs are written here by hand (no lmp needed): three samples, the
// third cut off in the middle of its contact entry.
TEST(LammpsBridge, RunStoppedMidWriteImportsAsPartialUpToItsLastSample) {
  const fs::path d = scratch("cut");
  const fs::path exp = d / "lammps";
  auto o = test_support::run_grainlift("export lammps " + (d / "tiny.toml").string() + " " +
                                       exp.string() + " --set output.fields=false");
  ASSERT_EQ(o.code, 0) << o.output;
  long long grains = 0, walls = 0;
  {
    std::ifstream m(exp / "export.txt");
    std::string key;
    long long v;
    std::string line;
    while (std::getline(m, line)) {
      std::istringstream s(line);
      if (s >> key >> v) {
        if (key == "grains") grains = v;
        if (key == "walls") walls = v;
      }
    }
  }
  ASSERT_GT(grains, 0);
  const long long intruder = grains + walls + 1;
  // one grain pressing on the intruder from +x: normal force on the intruder -1 N/m along x
  const std::string entry = std::to_string(intruder) + " 1 0.06 -1 0 -1 0 0 0\n";
  auto block = [&](int step) {
    return "ITEM: TIMESTEP\n" + std::to_string(step) + "\nITEM: NUMBER OF ENTRIES\n1\n"
           "ITEM: BOX BOUNDS pp ff pp\n0 1\n0 1\n0 1\nITEM: ENTRIES a b c d e f g h i\n" + entry;
  };
  std::ofstream(exp / "forces.txt") << "# fix\n# step t fx fy tq\n0 0 0 0 0\n20 4e-05 -1 0 0\n"
                                       "40 8e-05 -1 0 0\n60 0.00012 -1 0 0\n";
  std::string dump = block(0) + block(20) + block(40) + block(60);
  dump.resize(dump.size() - 12);  // the last entry cut short
  std::ofstream(exp / "contacts.dump") << dump;
  o = test_support::run_grainlift("import lammps " + exp.string() + " --out " +
                                  (d / "out").string());
  ASSERT_EQ(o.code, 0) << o.output;
  const RunResult r = read_result((d / "out" / "dem.h5").string());
  EXPECT_TRUE(r.meta.partial);
  ASSERT_TRUE(r.forces);
  EXPECT_EQ(r.forces->time.size(), 2u);  // steps 20 and 40
  EXPECT_EQ(r.forces->contacts[1], 1.0);
  EXPECT_NE(r.meta.notes.find("mid-write"), std::string::npos) << r.meta.notes;
  // the same damage before the end is a bad file
  std::ofstream(exp / "contacts.dump") << block(0) + "garbage\n" + block(20);
  o = test_support::run_grainlift("import lammps " + exp.string() + " --out " +
                                  (d / "out2").string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("contacts.dump:"), std::string::npos) << o.output;
}
