// The run driver: each solver's result lands in <out>/<solver>.h5 with the case verbatim and
// its hash; summary.json carries the stable names scripts rely on (drag, lift, torque,
// drag_stderr, lift_stderr, wall_seconds per solver, "compare" when both ran); a failing
// solver leaves earlier complete files untouched.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/run/run_driver.h"
#include "grainlift/shared/surface/surface_stress.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

const char* case_text = R"([domain]
x_range = [-0.5, 0.5]
y_range = [-0.5, 0.5]
[intruder]
diameter = 0.1
velocity = [1.0, 0.0]
[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.5
)";

SolverEntry fake(const std::string& name, double drag, double lift, bool with_stderr) {
  SolverEntry e;
  e.name = name;
  e.description = "fake";
  e.run = [=](const Case& c, const RunOptions&, ProgressReporter&) {
    RunResult r;
    r.geometry.intruder_diameter = c.intruder.diameter;
    r.geometry.velocity_x = c.intruder.velocity[0];
    r.geometry.pressure_scale = 100;
    MeanForces m;
    m.drag = drag;
    m.lift = lift;
    m.torque = 0.1;
    if (with_stderr) {
      m.drag_stderr = 0.5;
      m.lift_stderr = 0.25;
    }
    m.samples = 1;
    r.means = m;
    SurfaceDistribution s;
    s.theta = surface_angle_grid(16);
    s.sigma_n.assign(16, drag);
    s.sigma_t.assign(16, 0.0);
    r.surface = s;
    return r;
  };
  return e;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// A solver @p name whose run fails with RunError(@p why).
SolverEntry failing(const std::string& name, const std::string& why) {
  SolverEntry e = fake(name, 0, 0, false);
  e.run = [why](const Case&, const RunOptions&, ProgressReporter&) -> RunResult {
    throw RunError(why);
  };
  return e;
}

/// Quiet options writing to a folder of the temporary directory named @p name and this
/// process.
RunOptions quiet_options(const std::string& name) {
  RunOptions opt;
  opt.out_dir = (fs::temp_directory_path() / (name + "_" + std::to_string(getpid()))).string();
  opt.progress = false;
  return opt;
}

}  // namespace

TEST(RunDriver, WritesFilesAndSummaryWithStableNames) {
  const Case c = parse_case(case_text, "fake.toml", {"intruder.omega=3.0"});
  RunOptions opt = quiet_options("grainlift_driver");
  const fs::path out = opt.out_dir;
  run_solvers(c, {fake("dem", 10, -2, true), fake("fem", 12, -1, false)}, opt);

  const RunResult dem = read_result((out / "dem.h5").string());
  EXPECT_EQ(dem.meta.solver, "dem");
  EXPECT_EQ(dem.meta.case_text, case_text);
  EXPECT_EQ(dem.meta.case_overrides, "intruder.omega=3.0\n");
  EXPECT_EQ(dem.meta.case_hash, c.source.hash);
  EXPECT_GE(dem.meta.wall_seconds, 0.0);

  const std::string json = slurp(out / "summary.json");
  for (const char* key : {"\"dem\"", "\"fem\"", "\"compare\"", "\"drag\"", "\"lift\"",
                          "\"torque\"", "\"drag_stderr\"", "\"lift_stderr\"", "\"wall_seconds\"",
                          "\"drag_rel\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  // fem has no standard errors: null, never 0
  EXPECT_NE(json.find("\"drag_stderr\": null"), std::string::npos) << json;
  // drag_rel = (12 - 10) / 10 = 0.2 exactly representable to 1e-15
  EXPECT_NE(json.find("\"drag_rel\": 0.2"), std::string::npos) << json;
}

TEST(RunDriver, FailingSolverLeavesEarlierFilesComplete) {
  const Case c = parse_case(case_text, "fake.toml");
  RunOptions opt = quiet_options("grainlift_driver2");
  const fs::path out = opt.out_dir;
  run_solvers(c, {fake("dem", 10, -2, true)}, opt);
  const SolverEntry broken = failing("dem", "diverged at step 12");
  EXPECT_THROW(run_solvers(c, {broken}, opt), RunError);
  const RunResult back = read_result((out / "dem.h5").string());
  EXPECT_DOUBLE_EQ(back.means->drag, 10);  // the old complete file survives
}

TEST(RunDriver, SolversThatFinishedAreSummarisedWhenALaterOneFails) {
  const Case c = parse_case(case_text, "fake.toml");
  RunOptions opt = quiet_options("grainlift_driver3");
  const fs::path out = opt.out_dir;
  const SolverEntry broken = failing("fem", "did not converge");
  EXPECT_THROW(run_solvers(c, {fake("dem", 7, -1, true), broken}, opt), RunError);
  const std::string json = slurp(out / "summary.json");
  EXPECT_NE(json.find("\"dem\""), std::string::npos) << json;
  EXPECT_EQ(json.find("\"fem\""), std::string::npos) << json;
}

namespace {
/// Two fake solvers that each wait (up to 30 s) until the other has started: run one after
/// the other, the first would wait out its whole timeout.
struct Rendezvous {
  std::mutex m;
  std::condition_variable cv;
  int started = 0;
  /// Marks a start and waits for both; true when both started within the timeout.
  bool meet() {
    std::unique_lock<std::mutex> lock(m);
    ++started;
    cv.notify_all();
    return cv.wait_for(lock, std::chrono::seconds(30), [&] { return started == 2; });
  }
};

SolverEntry meeting(const std::string& name, double drag, Rendezvous& r, bool& met) {
  SolverEntry e = fake(name, drag, -1, false);
  const auto inner = e.run;
  e.run = [inner, &r, &met](const Case& c, const RunOptions& o, ProgressReporter& p) {
    met = r.meet();
    return inner(c, o, p);
  };
  return e;
}
}  // namespace

// `--threads 2` with both solvers (RunOptions::side_by_side): the DEM and the continuum run at
// once, each solver's file and the summary are what they are when the two run in turn, and
// the results come back in the solvers' order.
TEST(RunDriver, SideBySideSolversRunAtOnceAndWriteTheSameFiles) {
  const Case c = parse_case(case_text, "fake.toml");
  RunOptions opt = quiet_options("grainlift_driver4");
  const fs::path out = opt.out_dir;
  opt.side_by_side = true;
  Rendezvous r;
  bool dem_met = false, fem_met = false;
  const auto results =
      run_solvers(c, {meeting("dem", 10, r, dem_met), meeting("fem", 12, r, fem_met)}, opt);
  EXPECT_TRUE(dem_met && fem_met) << "the solvers did not run at the same time";
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].meta.solver, "dem");
  EXPECT_EQ(results[1].meta.solver, "fem");
  EXPECT_DOUBLE_EQ(read_result((out / "dem.h5").string()).means->drag, 10);
  EXPECT_DOUBLE_EQ(read_result((out / "fem.h5").string()).means->drag, 12);
  const std::string json = slurp(out / "summary.json");
  EXPECT_NE(json.find("\"compare\""), std::string::npos) << json;
  // drag_rel = (12 - 10) / 10, as in turn (WritesFilesAndSummaryWithStableNames)
  EXPECT_NE(json.find("\"drag_rel\": 0.2"), std::string::npos) << json;
}

// Side by side, a solver that fails does not take the other's result with it: the other's
// file is written and summarised, and the failure still ends the command (exit 1).
TEST(RunDriver, SideBySideFailureKeepsTheOtherSolversResult) {
  const Case c = parse_case(case_text, "fake.toml");
  RunOptions opt = quiet_options("grainlift_driver5");
  const fs::path out = opt.out_dir;
  opt.side_by_side = true;
  const SolverEntry broken = failing("dem", "diverged at step 12");
  EXPECT_THROW(run_solvers(c, {broken, fake("fem", 12, -1, false)}, opt), RunError);
  EXPECT_DOUBLE_EQ(read_result((out / "fem.h5").string()).means->drag, 12);
  EXPECT_FALSE(fs::exists(out / "dem.h5"));
  const std::string json = slurp(out / "summary.json");
  EXPECT_NE(json.find("\"fem\""), std::string::npos) << json;
  EXPECT_EQ(json.find("\"dem\""), std::string::npos) << json;
}
