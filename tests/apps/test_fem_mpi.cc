// The continuum solver under `mpirun -np 2` (distributed mesh, Trilinos linear algebra, amg).
// Physics: the partition of the mesh between ranks changes neither the mesh, nor the
// boundary conditions, nor the discrete equations, so the converged discrete solution may
// differ from the one-process run only by the tolerances of the solves (nonlinear 1e-8 |R_0|,
// inexact FGMRES steps): forces, torque, surface stresses and fields must agree to 1e-6
// relative (measured: ~1e-14), with the amg solver and with the direct one (UMFPACK on one
// process, MUMPS on two), after adaptive cycles too (both meshes limit level jumps across
// vertices, so they refine the same cells).
// Failures: one raised on every rank (bad input, no convergence) is reported once with its
// usual exit code; one raised on a single rank ends all ranks (MPI_Abort) instead of leaving
// the others waiting in a collective call.
// Skipped when mpirun is not installed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "grainlift/shared/results/result_file.h"
#include "run_command.h"

namespace fs = std::filesystem;

namespace {

std::string mpirun(int ranks) {
  return "mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
}

int run(const std::string& command, std::string* output) {
  const grainlift::test_support::CommandOutcome o = grainlift::test_support::run_command(command);
  if (output) *output = o.output;
  return o.code;
}

// Kumar-like spinning cylinder (lift, drag and torque all non-zero), refinement 1: 432 cells.
const char* fem_case = R"([domain]
x_range = [-0.6, 0.6]
y_range = [-0.4, 0.4]
[intruder]
diameter = 0.1
velocity = [1.0, 0.0]
omega = 40.0
[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.8
[continuum]
ambient_pressure = 1000.0
delta = 1.0                    # 1/s: a short continuation (the ranks solve any delta alike)
far_field = "open"             # (the periodic far field: its own test)
refinement = 1
linear_solver = "amg"
[output]
fields = true
field_spacing = 2.0
)";

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag)
      : path(fs::temp_directory_path() /
             ("grainlift_fem_mpi_" + tag + std::to_string(::getpid()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

bool have_mpirun() { return std::system("command -v mpirun > /dev/null 2>&1") == 0; }

/// max |a - b| / max |a| over the finite entries; the NaN patterns must be equal.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    EXPECT_EQ(std::isfinite(a[i]), std::isfinite(b[i])) << "entry " << i;
    if (!std::isfinite(a[i]) || !std::isfinite(b[i])) continue;
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return scale > 0 ? diff / scale : diff;
}

/// `grainlift @p verb` of the case with @p extra settings into dir/@p sub: on one process without
/// mpirun (@p ranks = 1), else under mpirun -np @p ranks; @p prefix goes before it all (an
/// environment setting, `timeout`). Returns the exit code.
int run_case(const TempDir& dir, const std::string& extra, int ranks, const std::string& sub,
             std::string& log, const std::string& verb = "run", const std::string& prefix = "") {
  std::ofstream(dir.path / "case.toml") << fem_case;
  const std::string command = prefix + (ranks > 1 ? mpirun(ranks) : std::string()) +
                              GRAINLIFT_BINARY + " " + verb + " " +
                              (dir.path / "case.toml").string() + " --solver fem" + extra +
                              " --out " + (dir.path / sub).string();
  return run(command, &log);
}

/// The case with @p extra settings run on one process (into dir/one) and on two ranks (dir/two).
void run_one_and_two(const TempDir& dir, const std::string& extra, std::string& log_two) {
  std::string log_one;
  ASSERT_EQ(run_case(dir, extra, 1, "one", log_one), 0) << log_one;
  ASSERT_EQ(run_case(dir, extra, 2, "two", log_two), 0) << log_two;
}

/// The same discrete solution to @p tol relative: drag, lift, torque, sigma_n and sigma_t, and
/// (@p with_fields) every field present in both.
void expect_same_solution(const std::string& tag, const grainlift::RunResult& a,
                          const grainlift::RunResult& b, double tol = 1e-6,
                          bool with_fields = true) {
  ASSERT_TRUE(a.means && b.means && a.surface && b.surface);
  const double drag = std::abs(a.means->drag);
  ASSERT_GT(drag, 0);
  EXPECT_NEAR(b.means->drag, a.means->drag, tol * drag);
  EXPECT_NEAR(b.means->lift, a.means->lift, tol * drag);
  EXPECT_NEAR(b.means->torque, a.means->torque, tol * std::abs(a.means->torque));
  EXPECT_LT(relative_difference(a.surface->sigma_n, b.surface->sigma_n), tol);
  EXPECT_LT(relative_difference(a.surface->sigma_t, b.surface->sigma_t), tol);
  EXPECT_EQ(a.fields.has_value(), b.fields.has_value());
  if (with_fields && a.fields && b.fields)
    for (const auto member : {&grainlift::FieldGrid::velocity_x, &grainlift::FieldGrid::velocity_y,
                              &grainlift::FieldGrid::pressure, &grainlift::FieldGrid::stress_xx,
                              &grainlift::FieldGrid::stress_xy, &grainlift::FieldGrid::stress_yy}) {
      ASSERT_TRUE((*a.fields).*member && (*b.fields).*member);
      EXPECT_LT(relative_difference(*((*a.fields).*member), *((*b.fields).*member)), tol);
    }
  std::printf("%s: drag %.12g / %.12g, lift %.12g / %.12g, torque %.12g / %.12g (a / b)\n",
              tag.c_str(), a.means->drag, b.means->drag, a.means->lift, b.means->lift,
              a.means->torque, b.means->torque);
}

/// Active cells of the final mesh, from /diagnostics; -1 if absent.
long cells_of(const grainlift::RunResult& r) {
  const auto& counts = r.diagnostics.counts;
  const auto it = counts.find("cells");
  return it == counts.end() ? -1 : static_cast<long>(it->second);
}

/// Number of occurrences of @p what in @p text.
std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

/// The case with the direct solver (UMFPACK on one process, MUMPS on two), fields off, and
/// @p extra settings, on one and on two ranks: the same solution.
void expect_two_ranks_match_one(const std::string& tag, const std::string& extra) {
  const TempDir dir(tag);
  std::string log;
  ASSERT_NO_FATAL_FAILURE(run_one_and_two(
      dir, " --quiet --set continuum.linear_solver='\"direct\"' --set output.fields=false" + extra,
      log));
  expect_same_solution(tag, grainlift::read_result((dir.path / "one" / "fem.h5").string()),
                       grainlift::read_result((dir.path / "two" / "fem.h5").string()));
}

}  // namespace

TEST(FemMpi, TwoRanksGiveTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("match");
  std::string out2;
  ASSERT_NO_FATAL_FAILURE(run_one_and_two(dir, "", out2));
  std::printf("%s\n", out2.c_str());
  // the ranks solved together (the log says so) and only rank 0 reported
  EXPECT_NE(out2.find("(2 MPI ranks)"), std::string::npos);
  std::size_t reports = 0;
  for (std::size_t p = out2.find("results:"); p != std::string::npos;
       p = out2.find("results:", p + 1))
    ++reports;
  EXPECT_EQ(reports, 1u);

  // complete output: the result file with forces, surface stresses and fields, the summary,
  // the XDMF sidecar and the VTU (one file, one piece per rank)
  for (const char* f : {"fem.h5", "summary.json", "fem_fields.xmf", "fem_vtu/continuum.vtu"})
    EXPECT_TRUE(fs::exists(dir.path / "two" / f)) << f;
  const grainlift::RunResult a = grainlift::read_result((dir.path / "one" / "fem.h5").string());
  const grainlift::RunResult b = grainlift::read_result((dir.path / "two" / "fem.h5").string());
  ASSERT_TRUE(a.means && b.means && b.surface && b.fields && b.forces);
  ASSERT_TRUE(b.fields->velocity_x && b.fields->pressure && b.fields->stress_xy);
  EXPECT_EQ(b.surface->sigma_n.size(), 64u);
  EXPECT_EQ(b.fields->velocity_x->size(), b.fields->x.size() * b.fields->y.size());
  {
    std::ifstream vtu(dir.path / "two" / "fem_vtu" / "continuum.vtu");
    const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
    std::size_t pieces = 0;
    for (std::size_t p = text.find("<Piece"); p != std::string::npos;
         p = text.find("<Piece", p + 1))
      ++pieces;
    EXPECT_EQ(pieces, 2u);
    EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  }
  EXPECT_GT(std::abs(a.means->lift), 0.05 * std::abs(a.means->drag));  // a case with lift
  expect_same_solution("amg", a, b);
}

TEST(FemMpi, DirectSolverOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("direct", "");
}

// The Coulomb wall adds boundary-face terms (assembled by the rank that owns the face) and
// the linearised gravity an extra linear solve and the central-difference outputs: neither
// may depend on the partition either.
TEST(FemMpi, CoulombWallOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("coulomb", " --set continuum.wall='\"coulomb\"'");
}

// The periodic far field under a top edge: the pressure level is one constraint over the whole
// top (the mean pressure on it), gathered from both ranks' faces, and p4est is told the
// periodic faces: the one-rank solution (direct solver; and with an adaptive cycle, which
// refines across the periodic ends alike on one and two ranks).
TEST(FemMpi, PeriodicBoxUnderALidOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("periodic", " --set continuum.far_field='\"periodic\"'");
  expect_two_ranks_match_one("periodic_adaptive", " --set continuum.far_field='\"periodic\"'"
                                                  " --set continuum.refinement=0"
                                                  " --set continuum.adaptive_cycles=1");
}

// continuum.wall_layers builds its rings into the coarse mesh, which p4est then refines: the
// same cells and the one-rank solution on two ranks (the periodic box, whose ends p4est
// balances; refinement 0, where only the block, rings included, is refined once).
TEST(FemMpi, WallLayersOnTwoRanksGiveTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("wall_layers", " --set continuum.wall_layers=2"
                                            " --set continuum.far_field='\"periodic\"'"
                                            " --set continuum.refinement=0");
}

TEST(FemMpi, LinearisedGravityOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("linearised", " --set scene.gravity=[0.0,-9.81]"
                                           " --set continuum.gravity_treatment='\"linearised\"'");
}

// One adaptive cycle from refinement 0 (direct solver). Kelly's indicator of a cell does not
// depend on the partition and the 30% are counted over all ranks, so two ranks mark the cells
// one process marks; p4est's 2:1 balance across vertices refines a cell that touches a cell two
// levels finer at a corner only, and so does the serial mesh (limit_level_difference_at_vertices):
// the same refined mesh (225 cells: 4 of them refined for that rule next to the block corners),
// the same discrete equations, so the same solution, fields included (measured ~1e-14). Checks
// the distributed estimate, the parallel marking and the transfer of the solution.
TEST(FemMpi, AdaptiveCycleOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("adaptive");
  std::string log_two;
  ASSERT_NO_FATAL_FAILURE(run_one_and_two(dir,
                                          " --set continuum.linear_solver='\"direct\"'"
                                          " --set continuum.refinement=0"
                                          " --set continuum.adaptive_cycles=1",
                                          log_two));
  const grainlift::RunResult one = grainlift::read_result((dir.path / "one" / "fem.h5").string());
  const grainlift::RunResult two = grainlift::read_result((dir.path / "two" / "fem.h5").string());
  EXPECT_NE(log_two.find("adaptive cycle 1 of 1"), std::string::npos) << log_two;
  std::printf("cells: %ld on one process, %ld on two ranks\n", cells_of(one), cells_of(two));
  EXPECT_GT(cells_of(one), 108);  // refinement 0 has 108 cells: the cycle refined
  EXPECT_EQ(cells_of(two), cells_of(one));
  expect_same_solution("adaptive", one, two);
}

// `grainlift sweep` would run every member on every rank: refused under mpirun, on every rank
// before anything is run or written; the refusal is printed once (by rank 0), exit 2.
TEST(FemMpi, UnsupportedOptionsOnTwoRanksAreRejectedCleanly) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("reject");
  const fs::path out_dir = dir.path / "out";
  std::string out;
  const int rc = run_case(dir, " --vary continuum.refinement=0,1", 2, "out", out, "sweep");
  std::printf("%s\n", out.c_str());
  EXPECT_EQ(rc, 2);  // bad input
  EXPECT_EQ(count_of(out, "bad input"), 1u);
  EXPECT_EQ(count_of(out, "sweep runs on one MPI process only"), 1u);
  EXPECT_FALSE(fs::exists(out_dir));
}

// A failure that every rank raises together ends the run as on one process: a value out of
// range (every rank reads the case: exit 2) and a solve that does not converge (the residual
// norms are global, so every rank stops: exit 1) are reported once, by rank 0, without
// MPI_Abort.
TEST(FemMpi, FailureOnEveryRankIsReportedOnce) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("every");
  struct Failure { const char* set; int code; const char* message; };
  for (const Failure f : {Failure{"continuum.refinement=9", 2, "bad input"},
                          Failure{"continuum.max_iterations=1", 1, "did not converge"}}) {
    std::string out;
    const int rc = run_case(dir, " --quiet --set continuum.refinement=0 --set " +
                                     std::string(f.set), 2, "out", out);
    std::printf("%s\n", out.c_str());
    EXPECT_EQ(rc, f.code) << f.set;
    EXPECT_EQ(count_of(out, f.message), 1u) << f.set;
    EXPECT_EQ(count_of(out, "grainlift: "), 1u) << f.set;  // one report in all
    EXPECT_EQ(out.find("MPI_ABORT"), std::string::npos) << f.set;
  }
}

// A failure on one rank only (here the test hook GRAINLIFT_TEST_FAIL_ON_RANK=1: rank 1 throws
// just before the nonlinear solve, while rank 0 goes on into the solve's collective calls)
// must not leave rank 0 waiting forever: rank 1 waits for the others to fail with it
// (MpiSession::kFailureWaitSeconds, 10 s; here 1 s by the hook
// GRAINLIFT_TEST_FAILURE_WAIT_SECONDS, while rank 0 spins in a collective call), prints its
// message with its rank and ends both with MPI_Abort. Non-zero exit within the 60 s of
// `timeout` (exit 124 would mean a hang), no result.
TEST(FemMpi, FailureOnOneRankEndsEveryRank) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("one_rank");
  const fs::path out_dir = dir.path / "out";
  std::string out;
  const int rc = run_case(dir, " --quiet --set continuum.refinement=0", 2, "out", out, "run",
                          "GRAINLIFT_TEST_FAIL_ON_RANK=1 GRAINLIFT_TEST_FAILURE_WAIT_SECONDS=1 "
                          "timeout 60 ");
  std::printf("%s\n", out.c_str());
  EXPECT_NE(rc, 0);
  EXPECT_NE(rc, 124) << "timed out: the ranks hung";
  EXPECT_NE(out.find("grainlift: error on MPI rank 1 of 2: continuum solver failed: "
                     "GRAINLIFT_TEST_FAIL_ON_RANK=1"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(out_dir / "fem.h5"));
}

// An exception in the solve on one process (the test hook on rank 0) is a failed run with its
// message, exit 1, not a non-convergence.
TEST(FemMpi, ExceptionOnOneProcessIsAnErrorNotANonConvergence) {
  const TempDir dir("exception");
  std::string out;
  const int rc = run_case(dir, " --quiet --set continuum.refinement=0", 1, "out", out, "run",
                          "GRAINLIFT_TEST_FAIL_ON_RANK=0 ");
  std::printf("%s\n", out.c_str());
  EXPECT_EQ(rc, 1);
  EXPECT_NE(out.find("run failed: continuum solver failed: GRAINLIFT_TEST_FAIL_ON_RANK=0"),
            std::string::npos);
  EXPECT_EQ(out.find("did not converge"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path / "out" / "fem.h5"));
}

// The mesh-error estimate (continuum.mesh_error_estimate, on by default) is the change of the
// forces from the next coarser level (the nested level below the requested one; solved
// independently first with continuum.nested = false): the coarser forces written to
// /diagnostics are those of a run at refinement 0 (1e-10 relative: the same discrete
// problem), *_mesh_error is |fine - coarser|, and the requested level's forces are the same
// with and without the estimate (bit-equal: the estimate adds no solve to the path).
// What the estimate is worth is measured in docs/crosscheck.md (this case's lift is not yet
// monotone in the level: -189.6, -172.7, -196.8, -217.8 N/m at refinements 0-3, so no bound
// is asserted here).
TEST(FemMesh, TheMeshErrorEstimateIsTheChangeFromTheCoarserLevel) {
  const TempDir dir("mesh_error");
  std::string log;
  const std::string common = " --quiet --set output.fields=false";
  ASSERT_EQ(run_case(dir, common, 1, "with", log), 0) << log;
  ASSERT_EQ(run_case(dir, common + " --set continuum.mesh_error_estimate=false", 1, "without",
                     log),
            0)
      << log;
  ASSERT_EQ(run_case(dir, common + " --set continuum.refinement=0 --set "
                               "continuum.mesh_error_estimate=false",
                     1, "coarse", log),
            0)
      << log;
  const auto with = grainlift::read_result((dir.path / "with" / "fem.h5").string());
  const auto without = grainlift::read_result((dir.path / "without" / "fem.h5").string());
  const auto coarse = grainlift::read_result((dir.path / "coarse" / "fem.h5").string());
  ASSERT_TRUE(with.means && without.means && coarse.means);
  EXPECT_EQ(with.means->drag, without.means->drag);
  EXPECT_EQ(with.means->lift, without.means->lift);
  EXPECT_EQ(with.means->torque, without.means->torque);
  const auto& v = with.diagnostics.values;
  ASSERT_TRUE(v.count("drag_coarser") && v.count("lift_mesh_error") && v.count("torque_coarser"));
  EXPECT_EQ(with.diagnostics.counts.at("coarser_refinement"), 0);
  EXPECT_NEAR(v.at("drag_coarser"), coarse.means->drag, 1e-10 * std::abs(coarse.means->drag));
  EXPECT_NEAR(v.at("lift_coarser"), coarse.means->lift, 1e-10 * std::abs(coarse.means->drag));
  EXPECT_NEAR(v.at("torque_coarser"), coarse.means->torque,
              1e-10 * std::abs(coarse.means->torque));
  EXPECT_NEAR(v.at("drag_mesh_error"), std::abs(with.means->drag - coarse.means->drag),
              1e-10 * std::abs(coarse.means->drag));
  EXPECT_NEAR(v.at("lift_mesh_error"), std::abs(with.means->lift - coarse.means->lift),
              1e-10 * std::abs(coarse.means->drag));
  EXPECT_FALSE(without.diagnostics.values.count("drag_mesh_error"));
  EXPECT_FALSE(coarse.diagnostics.values.count("drag_mesh_error"));  // refinement 0: no coarser
}

// The nonlocal fluidity solves every nested level (from the coarser one's g and flow), so its
// mesh-error estimate is the change of its own forces from the level below: the coarser
// forces in /diagnostics are those of a nonlocal run at refinement 0 (the same discrete
// problem on the same path: the local continuation, then the splitting, on that mesh; 1e-10
// relative), and *_mesh_error is |fine - coarser|.
TEST(FemMesh, TheNonlocalMeshErrorEstimateIsTheChangeFromItsCoarserLevel) {
  const TempDir dir("nonlocal_mesh_error");
  std::string log;
  const std::string common = " --quiet --set output.fields=false --set "
                             "continuum.linear_solver='\"direct\"' --set "
                             "continuum.model='\"nonlocal_fluidity\"' --set "
                             "continuum.nonlocal_amplitude=0.5";
  ASSERT_EQ(run_case(dir, common, 1, "fine", log), 0) << log;
  ASSERT_EQ(run_case(dir, common + " --set continuum.refinement=0", 1, "coarse", log), 0) << log;
  const auto fine = grainlift::read_result((dir.path / "fine" / "fem.h5").string());
  const auto coarse = grainlift::read_result((dir.path / "coarse" / "fem.h5").string());
  ASSERT_TRUE(fine.means && coarse.means);
  const auto& v = fine.diagnostics.values;
  ASSERT_TRUE(v.count("drag_coarser") && v.count("drag_mesh_error")) << log;
  const double scale = std::abs(coarse.means->drag);
  EXPECT_NEAR(v.at("drag_coarser"), coarse.means->drag, 1e-10 * scale);
  EXPECT_NEAR(v.at("lift_coarser"), coarse.means->lift, 1e-10 * scale);
  EXPECT_NEAR(v.at("drag_mesh_error"), std::abs(fine.means->drag - coarse.means->drag),
              1e-10 * scale);
  std::printf("nonlocal drag %.8g (refinement 1) against %.8g (0): mesh error %.4g\n",
              fine.means->drag, coarse.means->drag, v.at("drag_mesh_error"));
}
