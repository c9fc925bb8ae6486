// The `grainlift` command: documented exit codes (0 ok, 2 bad input) and messages that name
// the file, line and accepted range; `compare --json` on files that differ by a known amount.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/results/result_schema.h"
#include "grainlift/shared/surface/surface_stress.h"
#include "run_command.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

using Outcome = test_support::CommandOutcome;

Outcome run(const std::string& args) { return test_support::run_grainlift(args); }

fs::path scratch() {
  fs::path d = fs::temp_directory_path() / ("grainlift_cli_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

const std::string src = GRAINLIFT_SOURCE_DIR;

}  // namespace

TEST(Cli, HelpForEverySubcommandExitsZero) {
  for (const char* sub : {"", "run", "validate", "compare", "sweep", "keys", "schema"}) {
    const Outcome o = run(std::string(sub) + " --help");
    EXPECT_EQ(o.code, 0) << sub << "\n" << o.output;
    EXPECT_NE(o.output.find("Usage"), std::string::npos) << o.output;
  }
}

TEST(Cli, SchemaPrintsTheTable) {
  // `grainlift schema --markdown` is exactly the table docs/schema.md embeds; the plain text
  // has one line per entry below its header.
  const Outcome md = run("schema --markdown");
  EXPECT_EQ(md.code, 0);
  EXPECT_EQ(md.output, schema_markdown());
  const Outcome text = run("schema");
  EXPECT_EQ(text.code, 0);
  EXPECT_EQ(text.output, schema_text());
  EXPECT_EQ(std::count(text.output.begin(), text.output.end(), '\n'),
            std::ptrdiff_t(result_schema().size() + 1));
}

TEST(Cli, ValidateAcceptsShippedCasesAndRejectsBadOnesWithExitCode2) {
  EXPECT_EQ(run("validate " + src + "/cases/demo/demo.toml").code, 0);
  const fs::path bad = scratch() / "bad.toml";
  std::ofstream(bad) << "[domain]\nx_range = [-1.0, 1.0]\ny_range = [-1.0, 1.0]\n"
                        "[intruder]\ndiameter = 0.1\nvelocity = [1.0, 0.0]\n"
                        "[grains]\ndiameter = 0.01\ndensity = 20.0\narea_fraction = 2.0\n";
  const Outcome o = run("validate " + bad.string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.output.find(bad.string() + ":10:"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("accepted: (0, 0.9]"), std::string::npos) << o.output;
  // the same error through `run`, and a bad --set on a good file
  EXPECT_EQ(run("run " + bad.string() + " --solver dem --quiet").code, 2);
  const Outcome s = run("validate " + src + "/cases/demo/demo.toml --set grains.friction=abc");
  EXPECT_EQ(s.code, 2);
  EXPECT_NE(s.output.find("--set 'grains.friction=abc'"), std::string::npos) << s.output;
}

TEST(Cli, BadOptionsAndMissingFilesExitWith2) {
  EXPECT_EQ(run("run " + src + "/cases/demo/demo.toml --solver lbm").code, 2);
  EXPECT_EQ(run("run /nonexistent.toml").code, 2);
  EXPECT_EQ(run("compare /nonexistent_a.h5 /nonexistent_b.h5").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
}

TEST(Cli, CompareJsonReportsKnownDifferences) {
  // A and B differ by +20 % drag and a uniform 0.1 P shift of sigma_n (P = 50 Pa).
  auto make = [](double drag, double shift) {
    RunResult r;
    r.meta.solver = "dem";
    r.geometry.pressure_scale = 50;
    MeanForces m;
    m.drag = drag;
    m.lift = -1;
    m.torque = 0.5;
    r.means = m;
    SurfaceDistribution s;
    s.theta = surface_angle_grid(32);
    for (double t : s.theta) {
      s.sigma_n.push_back(50 * (1 + std::cos(t)) + shift);
      s.sigma_t.push_back(0);
    }
    r.surface = s;
    return r;
  };
  const fs::path d = scratch();
  write_result((d / "a.h5").string(), make(10, 0));
  write_result((d / "b.h5").string(), make(12, 5));
  const Outcome o =
      run("compare " + (d / "a.h5").string() + " " + (d / "b.h5").string() + " --json");
  ASSERT_EQ(o.code, 0) << o.output;
  auto value = [&](const std::string& key) {
    const auto p = o.output.find("\"" + key + "\": ");
    EXPECT_NE(p, std::string::npos) << key << "\n" << o.output;
    return std::stod(o.output.substr(p + key.size() + 4));
  };
  EXPECT_NEAR(value("drag_rel"), 0.2, 1e-12);
  EXPECT_NEAR(value("lift_rel"), 0.0, 1e-12);
  EXPECT_NEAR(value("sigma_n_l2"), 0.1, 1e-12);
  EXPECT_NEAR(value("sigma_n_max"), 0.1, 1e-12);
  EXPECT_NEAR(value("pressure_scale"), 50, 1e-12);
}
