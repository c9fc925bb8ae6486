// The whole chain through the real command on a tiny DEM case: `run` writes dem.h5 that h5
// readers see with every DEM block present (forces, means with standard errors, surface,
// histogram, fields) and summary.json; `sweep` writes one CSV row per value; a dt above the
// stated fraction of the collision time is bad input (exit 2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "grainlift/shared/statistics/statistics.h"
#include "run_command.h"
#include "tiny_dem_case.h"

using namespace grainlift;
namespace fs = std::filesystem;
using test_support::tiny_case;

namespace {

int run(const std::string& args, std::string* output = nullptr) {
  const test_support::CommandOutcome o = test_support::run_grainlift(args);
  if (output) *output = o.output;
  return o.code;
}

fs::path scratch() {
  fs::path d = fs::temp_directory_path() / ("grainlift_e2e_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(EndToEnd, DemRunWritesEveryDemBlockAndSummary) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(run("run " + (d / "tiny.toml").string() + " --solver dem --quiet --out " +
                    (d / "run").string(), &out),
            0)
      << out;
  const RunResult r = read_result((d / "run" / "dem.h5").string());
  ASSERT_TRUE(r.forces && r.means && r.surface && r.histogram && r.fields);
  EXPECT_EQ(r.meta.solver, "dem");
  EXPECT_TRUE(r.means->drag_stderr.has_value());
  EXPECT_EQ(r.surface->theta.size(), 64u);
  EXPECT_EQ(r.histogram->theta_lo.size(), 24u);
  EXPECT_TRUE(r.fields->area_fraction && r.fields->granular_temperature);
  // the intruder pushes grains forward: mean drag is positive (resists motion)
  EXPECT_GT(r.means->drag, 0.0);
  // time-series consistency: mean drag equals -mean fx over the averaged samples (V along +x)
  double fx = 0;
  const std::size_t n = std::size_t(r.means->samples);
  for (std::size_t i = r.forces->fx.size() - n; i < r.forces->fx.size(); ++i) fx += r.forces->fx[i];
  EXPECT_NEAR(r.means->drag, -fx / double(n), 1e-9 * std::abs(r.means->drag));
  // one statistics rule: the stored error is statistics.h's correlation-corrected block error
  // of the averaged series, the error dem.target_error and the shear cell use (exactly: the
  // same function on the same samples)
  std::vector<double> drag;
  for (std::size_t i = r.forces->fx.size() - n; i < r.forces->fx.size(); ++i)
    drag.push_back(-r.forces->fx[i]);
  const BlockMean b = block_mean(drag, std::size_t(r.means->blocks));
  EXPECT_EQ(*r.means->drag_stderr, b.stderr_corrected);
  EXPECT_GE(b.stderr_corrected, b.stderr_);
  EXPECT_TRUE(fs::exists(d / "run" / "summary.json"));
  EXPECT_TRUE(fs::exists(d / "run" / "dem_fields.xmf"));
  // the travel the means come from, and the intruder's own wake: in a periodic box 20 d long
  // the intruder (5 d) meets the bed it disturbed after 20 - 5 = 15 d; 10 d stop before it
  EXPECT_EQ(r.diagnostics.values.at("mean_travel_from"), 2.0);
  EXPECT_NEAR(r.diagnostics.values.at("mean_travel_to"), 10.0, 1e-9);
  EXPECT_NEAR(r.diagnostics.values.at("wake_travel"), 15.0, 1e-9);
  EXPECT_EQ(r.diagnostics.counts.at("crossed_own_wake"), 0);
}

// A run that goes past its wake says so (the continuum's periodic far field stands for it).
TEST(EndToEnd, DemRunPastItsWakeSaysSo) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(run("run " + (d / "tiny.toml").string() + " --solver dem --quiet --set dem.travel=16.0"
                " --set output.fields=false --out " + (d / "past").string(), &out),
            0)
      << out;
  const RunResult r = read_result((d / "past" / "dem.h5").string());
  EXPECT_NEAR(r.diagnostics.values.at("mean_travel_to"), 16.0, 1e-9);
  EXPECT_EQ(r.diagnostics.counts.at("crossed_own_wake"), 1);
}

// The DEM's per-angle standard errors of sigma_n (/surface/sigma_n_stderr, from the profiles of
// the force blocks) must say how far independent beds' profiles differ: over the angles where
// both have contacts, the rms of (sigma_n(seed i) - sigma_n(seed j)) / sqrt(se_i^2 + se_j^2) is
// about 1 when the errors are right. Measured over the 15 pairs of seeds 1-6: median 0.96,
// range 0.84-2.99; the pairs with seed 2 give 2.5-3.0 (that bed differs from the others by more
// than its time average's error: bed-to-bed scatter the block error does not contain, see
// issue 17). The median is asserted between 0.5 and 2 (5 blocks per run: each se from 4
// degrees of freedom); errors off by a factor 2 fail it.
TEST(EndToEnd, DemSurfaceStressErrorsMatchTheScatterBetweenBeds) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  constexpr int kBeds = 6;
  std::vector<RunResult> r(kBeds);
  for (int k = 0; k < kBeds; ++k) {
    std::string out;
    const std::string dir = (d / ("seed" + std::to_string(k))).string();
    ASSERT_EQ(run("run " + (d / "tiny.toml").string() + " --solver dem --quiet --set dem.seed=" +
                      std::to_string(k + 1) + " --out " + dir, &out),
              0)
        << out;
    r[k] = read_result(dir + "/dem.h5");
    ASSERT_TRUE(r[k].surface && r[k].surface->sigma_n_stderr && r[k].surface->sigma_t_stderr);
    ASSERT_EQ(r[k].surface->sigma_n_stderr->size(), r[k].surface->sigma_n.size());
    for (double se : *r[k].surface->sigma_n_stderr) EXPECT_TRUE(std::isfinite(se) && se >= 0);
  }
  std::vector<double> rms;
  for (int i = 0; i < kBeds; ++i)
    for (int j = i + 1; j < kBeds; ++j) {
      const auto &a = *r[i].surface, &b = *r[j].surface;
      double sum = 0;
      int n = 0;
      for (std::size_t m = 0; m < a.sigma_n.size(); ++m) {
        const double se_a = (*a.sigma_n_stderr)[m], se_b = (*b.sigma_n_stderr)[m];
        if (!(a.sigma_n[m] > 0 && b.sigma_n[m] > 0 && se_a > 0 && se_b > 0)) continue;
        const double z = (a.sigma_n[m] - b.sigma_n[m]) / std::hypot(se_a, se_b);
        sum += z * z;
        ++n;
      }
      ASSERT_GT(n, 16) << i << " " << j;  // the front half at least
      rms.push_back(std::sqrt(sum / n));
      std::printf("seeds %d, %d: rms z %.3f over %d angles\n", i + 1, j + 1, rms.back(), n);
    }
  std::sort(rms.begin(), rms.end());
  const double median = rms[rms.size() / 2];
  EXPECT_GT(median, 0.5);
  EXPECT_LT(median, 2.0);
}

// Physics: a lid at P = 200 Pa (2D: N/m per m) on the tiny bed, which is far below jamming
// (Phi 0.6), is not held up by the grains at first: it comes down (last height below the first)
// and the measured pressure stays below the target on average. The lid's series has one row per
// force sample and its mean, target, mass and damping reach /lid and summary.json.
TEST(EndToEnd, DemRunWithALidWritesTheLidSeries) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(
      run("run " + (d / "tiny.toml").string() +
              " --solver dem --quiet --set output.fields=false --set domain.lid_pressure=200.0"
              " --out " +
              (d / "lid").string(),
          &out),
      0)
      << out;
  const RunResult r = read_result((d / "lid" / "dem.h5").string());
  ASSERT_TRUE(r.lid && r.forces);
  EXPECT_EQ(r.lid->time, r.forces->time);
  EXPECT_EQ(r.lid->target, 200.0);
  EXPECT_GT(r.lid->mass, 0.0);
  EXPECT_GT(r.lid->damping, 0.0);
  EXPECT_TRUE(r.lid->mean_stderr.has_value());
  EXPECT_LT(r.lid->y.back(), r.lid->y.front());
  EXPECT_LT(r.lid->mean, 200.0);
  EXPECT_EQ(r.geometry.pressure_scale, 200.0);  // lid pressure, no gravity
  std::ifstream in(d / "lid" / "summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("\"lid_pressure_mean\""), std::string::npos) << summary;
}

TEST(EndToEnd, SweepWritesOneRowPerValue) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(run("sweep " + (d / "tiny.toml").string() +
                    " --solver dem --quiet --set output.fields=false --vary intruder.omega=0,40 "
                    "--out " + (d / "sweep").string(), &out),
            0)
      << out;
  std::ifstream in(d / "sweep" / "sweep.csv");
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u);  // header + 2 runs
  EXPECT_EQ(rows[0].rfind("key,value,solver,drag,drag_stderr,lift", 0), 0u);
  EXPECT_EQ(rows[1].rfind("intruder.omega,\"0\",dem,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("intruder.omega,\"40\",dem,", 0), 0u) << rows[2];
}

// dem.target_error: the run ends at the first progress check (every 1% of dem.travel) where
// the relative standard errors of the mean drag and lift (block averages corrected for
// correlated blocks) are both at or below the target. On the tiny bed, 200 d allowed and a
// target of 30%: measured a stop after 44 d with 22% and 29%. Asserted: it stops before the
// travel, the errors it reports are at or below the target, and the file's means are the
// samples actually run (steps / sample_every of them). A target out of reach (1% in 20 d)
// runs the whole travel and warns.
TEST(EndToEnd, DemRunStopsAtTheTargetError) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(run("run " + (d / "tiny.toml").string() +
                    " --solver dem --quiet --set output.fields=false --set output.blocks=20 "
                    "--set dem.travel=200 --set dem.target_error=0.3 --out " +
                    (d / "target").string(), &out),
            0)
      << out;
  RunResult r = read_result((d / "target" / "dem.h5").string());
  const auto& diag = r.diagnostics;
  ASSERT_EQ(diag.counts.at("target_error_reached"), 1);
  EXPECT_LT(diag.values.at("travel_run"), 200.0);
  EXPECT_LE(diag.values.at("drag_relative_error"), 0.3);
  EXPECT_LE(diag.values.at("lift_relative_error"), 0.3);
  EXPECT_LE(*r.means->drag_stderr / r.means->drag, 0.3);  // the error the target was met by
  const long long steps = diag.counts.at("steps");
  EXPECT_LT(steps, 1000000);  // 200 d at 2 m/s and dt 2e-6 s
  EXPECT_EQ(std::int64_t(r.forces->time.size()), steps / 20);  // sample_every = 20

  ASSERT_EQ(run("run " + (d / "tiny.toml").string() +
                    " --solver dem --set output.fields=false --set dem.travel=20 "
                    "--set dem.target_error=0.01 --out " + (d / "short").string(), &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: target error 1.0% not reached"), std::string::npos) << out;
  r = read_result((d / "short" / "dem.h5").string());
  EXPECT_EQ(r.diagnostics.counts.at("target_error_reached"), 0);
  EXPECT_EQ(r.diagnostics.counts.at("steps"), 100000);
}

// --replicas N runs N independent beds (seeds dem.seed + k) side by side and pools them: each
// replica's means are the bits of the same seed run alone (same code on one thread), the
// pooled drag is their mean and its error (statistics.h's pooled_mean) the larger of their
// standard deviation / sqrt(N) and sqrt(sum of their squared errors) / N.
TEST(EndToEnd, ReplicasPoolIndependentBeds) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  ASSERT_EQ(run("run " + (d / "tiny.toml").string() +
                    " --solver dem --quiet --replicas 3 --threads 2 --out " +
                    (d / "rep").string(), &out),
            0)
      << out;
  const RunResult pooled = read_result((d / "rep" / "dem.h5").string());
  const auto& drag = pooled.diagnostics.series.at("replica_drag");
  const auto& seeds = pooled.diagnostics.series.at("replica_seed");
  ASSERT_EQ(drag.size(), 3u);
  EXPECT_EQ(seeds, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(pooled.diagnostics.counts.at("replicas"), 3);
  double mean = 0, ss = 0;
  for (double x : drag) mean += x / 3;
  for (double x : drag) ss += (x - mean) * (x - mean);
  EXPECT_NEAR(pooled.means->drag, mean, 1e-12 * std::abs(mean));
  const double between = std::sqrt(ss / 2 / 3);
  EXPECT_GE(*pooled.means->drag_stderr, between - 1e-12 * std::abs(mean));
  EXPECT_EQ(pooled.means->blocks, 3);
  ASSERT_TRUE(pooled.surface && pooled.surface->sigma_n_stderr && pooled.fields);
  ASSERT_EQ(run("run " + (d / "tiny.toml").string() +
                    " --solver dem --quiet --set dem.seed=2 --out " + (d / "seed2").string(),
                &out),
            0)
      << out;
  const RunResult alone = read_result((d / "seed2" / "dem.h5").string());
  EXPECT_EQ(alone.means->drag, drag[1]);
  // the within part is at least this replica's own error / N
  EXPECT_GE(*pooled.means->drag_stderr, *alone.means->drag_stderr / 3 - 1e-12 * std::abs(mean));
  EXPECT_EQ(alone.means->lift, pooled.diagnostics.series.at("replica_lift")[1]);
}

TEST(EndToEnd, TooLargeTimeStepIsBadInput) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  std::string out;
  EXPECT_EQ(run("run " + (d / "tiny.toml").string() + " --solver dem --quiet --set dem.dt=1e-3 "
                "--out " + (d / "bad").string(), &out),
            2)
      << out;
  EXPECT_NE(out.find("collision time"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(d / "bad" / "dem.h5"));
}

// `grainlift calibrate` on Kumar's grains (the tiny case's, mu = 0.5) at P = 500 N/m and five
// inertial numbers from 0.01 to 0.5 at half the default strain (a few seconds; points on both
// sides of I0, without which mu_s is not determined and the fit refuses): the rheology file is
// written and reads back; the friction rises with I (mu(I) is increasing, GDR MiDi 2004;
// measured 0.29, 0.26 at I = 0.017, 0.024 and 0.35, 0.33 at I = 0.41, 0.65: a margin of 0.14
// for the 0.05 asserted), with a static friction mu_s of frictional disks between 0.1 and 0.4
// (da Cruz et al. 2005: about 0.26) and a random packing below 0.84. A case with no pressure of
// its own and no --pressure is bad input. With --threads 2 the points run side by side (two at
// a time, one thread each): the file is the one of --threads 1, byte for byte (the DEM's bits do
// not depend on its threads; the points are kept and fitted in the targets' order).
TEST(EndToEnd, CalibrateWritesAFittedRheologyFile) {
  const fs::path dir = scratch();
  const fs::path case_file = dir / "calibrate.toml";
  std::ofstream(case_file) << tiny_case;
  const fs::path law = dir / "law.toml", law_one = dir / "law_one_thread.toml";
  std::string out, out_one;
  const std::string sweep = "calibrate " + case_file.string() + " --pressure 500 "
                            "--inertial-numbers 0.01 0.03 0.1 0.2 0.5 --strain-scale 0.5 --out ";
  const int rc = run(sweep + law.string() + " --threads 2", &out);
  ASSERT_EQ(rc, 0) << out;
  ASSERT_EQ(run(sweep + law_one.string() + " --threads 1", &out_one), 0) << out_one;
  auto text = [](const fs::path& p) {
    std::ifstream in(p);
    std::string t((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return t;
  };
  EXPECT_EQ(text(law), text(law_one));
  EXPECT_NE(out.find("rheology file: " + law.string()), std::string::npos) << out;
  const RheologyFile f = read_rheology_file(law.string());
  ASSERT_GE(f.points.size(), 4u) << out;
  // the two fastest points against the two slowest (each point alone is +- 0.01 to 0.05)
  const auto& q = f.points;
  const std::size_t n = q.size();
  EXPECT_GT(q[n - 1].mu + q[n - 2].mu, q[0].mu + q[1].mu + 0.05) << out;
  EXPECT_GT(f.mu_i.mu_s, 0.1) << out;
  EXPECT_LT(f.mu_i.mu_s, 0.4) << out;
  EXPECT_GT(f.phi_i.phi_max, 0.6) << out;
  EXPECT_LT(f.phi_i.phi_max, 0.84) << out;
  const int bad = run("calibrate " + case_file.string() + " --out " + law.string(), &out);
  EXPECT_EQ(bad, 2) << out;
  EXPECT_NE(out.find("calibrate needs a pressure"), std::string::npos) << out;
  fs::remove_all(dir);
}

// `grainlift calibrate --nonlocal` on the demo's grains (one bed, a twentieth of the default
// travel: about 5 s): the cooperativity amplitude of the creeping-layer cell is added to the demo's
// rheology file as [nonlocal], the rest of the file reads back unchanged (mu_s, mu_2, I0 to
// the bit), A lies inside the searched range [0.01, 10] with an error bar (measured 0.21 +-
// 0.07), the fitted bins span mu from below 0.2 (the creeping bed, p up to 3 P0) to above the
// calibrated mu_s 0.239 (the sheared top), and the profile is written beside the file with a
// row per bin, each with its grains' hexatic order |psi6| in [0, 1] (last column). Without a
// rheology file to read mu_s from the command is bad input (exit 2).
TEST(EndToEnd, CalibrateNonlocalAddsTheCooperativityAmplitude) {
  const fs::path dir = scratch();
  const std::string demo = std::string(GRAINLIFT_SOURCE_DIR) + "/cases/demo/";
  const fs::path law = dir / "demo_law.toml";
  fs::copy_file(demo + "rheology.toml", law, fs::copy_options::overwrite_existing);
  const RheologyFile before = read_rheology_file(law.string());
  std::string out;
  const int rc = run("calibrate " + demo + "demo.toml --nonlocal --seeds 1 --strain-scale 0.05 "
                     "--quiet --out " + law.string(), &out);
  ASSERT_EQ(rc, 0) << out;
  const RheologyFile after = read_rheology_file(law.string());
  ASSERT_TRUE(after.nonlocal.has_value()) << out;
  EXPECT_EQ(after.mu_i.mu_s, before.mu_i.mu_s);
  EXPECT_EQ(after.mu_i.mu_2, before.mu_i.mu_2);
  EXPECT_EQ(after.mu_i.I0, before.mu_i.I0);
  EXPECT_EQ(after.points.size(), before.points.size());
  const Cooperativity& a = *after.nonlocal;
  EXPECT_GT(a.amplitude, 0.01) << out;
  EXPECT_LT(a.amplitude, 10.0) << out;
  EXPECT_GT(a.amplitude_err, 0.0) << out;
  EXPECT_LT(a.mu_min, 0.2) << out;
  EXPECT_GT(a.mu_max, before.mu_i.mu_s) << out;
  std::ifstream csv(dir / "demo_law.creep.csv");
  std::string line;
  int rows = 0;
  int ordered = 0;  // rows whose last column, the grains' |psi6|, lies in [0, 1]
  while (std::getline(csv, line)) {
    if (line.rfind("y_m,", 0) == 0) {
      EXPECT_EQ(line.substr(line.rfind(',') + 1), "psi6");
    }
    if (line.empty() || line[0] == '#' || line[0] == 'y') continue;
    ++rows;
    const double psi6 = std::strtod(line.c_str() + line.rfind(',') + 1, nullptr);
    if (psi6 >= 0 && psi6 <= 1) ++ordered;
  }
  EXPECT_GE(rows, a.points) << out;
  EXPECT_GE(ordered, a.points) << out;
  const int bad = run("calibrate " + demo + "demo.toml --nonlocal --out " +
                          (dir / "none.toml").string(), &out);
  EXPECT_EQ(bad, 2) << out;
  EXPECT_NE(out.find("does not exist; its mu_s is needed"), std::string::npos) << out;
  fs::remove_all(dir);
}

// A shear-cell point the DEM cannot run (Guillard's soft grains, E = 5 MPa, at I = 0.5 and
// P = 1.2 N/m: the linear start profile of a dense bed drives overlaps above 0.1 d within 230
// steps) is reported by name and left out of the fit; the calibration still fits the other
// points and writes the file. One bad point must not cost the user the whole sweep, nor the top
// of the range: the cell tries once more at sqrt(0.2 x 0.5) = 0.316, which these grains run
// (measured: 5 points fitted, the I = 0.5 one refused with the overlap it reached, the highest
// measured I about 0.29).
TEST(EndToEnd, CalibrateLeavesOutAPointTheCellCannotRun) {
  const fs::path dir = scratch();
  const fs::path case_file = dir / "soft.toml";
  std::ofstream(case_file) << R"([domain]
x_range = [-0.09, 0.09]
y_range = [-0.06, 0.06]
periodic = [true, false]
walls = ["bottom", "top"]
lid_pressure = 1.2066
[intruder]
diameter = 0.015
velocity = [0.05, 0.0]
[grains]
diameter = 0.0015
density = 2.5
area_fraction = 0.82
[grains.contact]
law = "guillard2014"
youngs_modulus = 5e6
poisson_ratio = 0.45
restitution = 0.6
[dem]
dt = 1e-5
packing_cache = ""
)";
  const fs::path law = dir / "law.toml";
  std::string out;
  // two threads: the points side by side, the retry after them (the file in the targets' order)
  const int rc = run("calibrate " + case_file.string() + " --inertial-numbers 0.01 0.03 0.1 "
                     "0.2 0.5 --threads 2 --out " + law.string(), &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("I target 0.5    FAILED, left out of the fit"), std::string::npos) << out;
  EXPECT_NE(out.find("overlap"), std::string::npos) << out;
  EXPECT_NE(out.find("I target 0.316  measured"), std::string::npos) << out;
  EXPECT_NE(out.find("(between 0.2 and 0.5, which the cell could not run)"), std::string::npos)
      << out;
  const RheologyFile f = read_rheology_file(law.string());
  EXPECT_EQ(f.points.size(), 5u) << out;
  EXPECT_GT(f.I_max, 0.22) << out;  // above the 0.2 point: the retried one is in the fit
  EXPECT_LT(f.I_max, 0.4) << out;
  fs::remove_all(dir);
}

// GRAINLIFT_SIMD chooses the DEM's vector target: every target this build and CPU run, as
// `grainlift --version` lists them (scalar always; avx2 and avx512 on an x86 CPU with them;
// neon, sve, ... on Arm), gives the same forces bit for bit as the scalar code (the step's
// contract), and summary.json and /diagnostics name the one used; a target that is not there
// (neon on x86, avx2 elsewhere) refuses the run with exit 1 and names the targets there are.
TEST(EndToEnd, EverySimdTargetGivesTheSameBitsAndIsNamed) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << tiny_case;
  const std::string runs = "run " + (d / "tiny.toml").string() + " --solver dem --quiet --out ";
  std::string out;
  ASSERT_EQ(run("--version", &out), 0) << out;
  // "DEM SIMD: avx512 (this build and CPU: scalar, avx2, avx512; GRAINLIFT_SIMD chooses one)"
  const std::string head = "this build and CPU: ";
  const std::size_t from = out.find(head);
  ASSERT_NE(from, std::string::npos) << out;
  const std::string list = out.substr(from + head.size(),
                                      out.find_first_of(";(", from) - from - head.size());
  std::vector<std::string> targets;
  std::istringstream names(list);
  for (std::string t; std::getline(names, t, ',');) {
    t.erase(0, t.find_first_not_of(' '));
    t.erase(t.find_last_not_of(' ') + 1);
    if (!t.empty()) targets.push_back(t);
  }
  ASSERT_FALSE(targets.empty()) << out;
  EXPECT_EQ(targets.front(), "scalar") << out;  // the reference, run first
  std::vector<double> reference_fx, reference_fy;
  for (const std::string& t : targets) {
    const fs::path o = d / ("simd_" + t);
    const auto ran = test_support::run_command("env GRAINLIFT_SIMD=" + t + " " +
                                               std::string(GRAINLIFT_BINARY) + " " + runs +
                                               o.string());
    ASSERT_EQ(ran.code, 0) << ran.output;
    const RunResult r = read_result((o / "dem.h5").string());
    EXPECT_EQ(r.diagnostics.texts.at("simd"), t);
    std::ifstream js(o / "summary.json");
    const std::string json((std::istreambuf_iterator<char>(js)), {});
    EXPECT_NE(json.find("\"simd\": \"" + t + "\""), std::string::npos) << json;
    if (reference_fx.empty()) {
      reference_fx = r.forces->fx;
      reference_fy = r.forces->fy;
    } else {
      EXPECT_EQ(r.forces->fx, reference_fx) << t << " against scalar";
      EXPECT_EQ(r.forces->fy, reference_fy) << t << " against scalar";
    }
  }
  std::printf("targets run: %s\n", list.c_str());
  const bool has_neon = std::find(targets.begin(), targets.end(), "neon") != targets.end();
  const std::string absent = has_neon ? "avx2" : "neon";
  const auto refused = test_support::run_command("env GRAINLIFT_SIMD=" + absent + " " +
                                                  std::string(GRAINLIFT_BINARY) + " " + runs +
                                                  (d / ("simd_" + absent)).string());
  EXPECT_EQ(refused.code, 1) << refused.output;
  EXPECT_NE(refused.output.find("GRAINLIFT_SIMD=" + absent +
                                ": the DEM's vector targets here are " + list),
            std::string::npos)
      << refused.output;
  fs::remove_all(d);
}
