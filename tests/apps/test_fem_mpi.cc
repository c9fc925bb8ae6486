// The continuum solver under `mpirun -np 2` (distributed mesh, Trilinos linear algebra, amg).
// Physics: the partition of the mesh between ranks changes neither the mesh, nor the
// boundary conditions, nor the discrete equations, so the converged discrete solution may
// differ from the one-process run only by the tolerances of the solves (nonlinear 1e-8 |R_0|,
// inexact FGMRES steps): forces, torque, surface stresses and fields must agree to 1e-6
// relative (measured: ~1e-14), with the amg solver and with the direct one (UMFPACK on one
// process, MUMPS on two). What the distributed solve does not support (adaptive cycles) must
// stop every rank with bad input (exit 2) before any file is written.
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

#include "grainlift/shared/result_file.h"
#include "run_command.h"

namespace fs = std::filesystem;

namespace {

const char* kMpirun = "mpirun --allow-run-as-root --oversubscribe -np 2 ";

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
refinement = 1
linear_solver = "amg"
[output]
fields = true
field_spacing = 2.0
)";

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag)
      : path(fs::temp_directory_path() / ("grainlift_fem_mpi_" + tag + std::to_string(::getpid()))) {
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

/// The case with @p extra settings run on one process (into dir/one) and on two ranks (dir/two).
void run_one_and_two(const TempDir& dir, const std::string& extra, std::string& log_two) {
  std::ofstream(dir.path / "case.toml") << fem_case;
  const std::string args =
      " run " + (dir.path / "case.toml").string() + " --solver fem" + extra + " --out ";
  std::string log_one;
  ASSERT_EQ(run(std::string(GRAINLIFT_BINARY) + args + (dir.path / "one").string(), &log_one), 0)
      << log_one;
  ASSERT_EQ(run(kMpirun + std::string(GRAINLIFT_BINARY) + args + (dir.path / "two").string(), &log_two), 0)
      << log_two;
}

/// The same discrete solution to 1e-6 relative: drag, lift, torque, sigma_n and sigma_t, and
/// every field present in both.
void expect_same_solution(const std::string& tag, const grainlift::RunResult& a,
                          const grainlift::RunResult& b) {
  ASSERT_TRUE(a.means && b.means && a.surface && b.surface);
  const double tol = 1e-6, drag = std::abs(a.means->drag);
  ASSERT_GT(drag, 0);
  EXPECT_NEAR(b.means->drag, a.means->drag, tol * drag);
  EXPECT_NEAR(b.means->lift, a.means->lift, tol * drag);
  EXPECT_NEAR(b.means->torque, a.means->torque, tol * std::abs(a.means->torque));
  EXPECT_LT(relative_difference(a.surface->sigma_n, b.surface->sigma_n), tol);
  EXPECT_LT(relative_difference(a.surface->sigma_t, b.surface->sigma_t), tol);
  EXPECT_EQ(a.fields.has_value(), b.fields.has_value());
  if (a.fields && b.fields)
    for (const auto member : {&grainlift::FieldGrid::velocity_x, &grainlift::FieldGrid::velocity_y,
                              &grainlift::FieldGrid::pressure, &grainlift::FieldGrid::stress_xx,
                              &grainlift::FieldGrid::stress_xy, &grainlift::FieldGrid::stress_yy}) {
      ASSERT_TRUE((*a.fields).*member && (*b.fields).*member);
      EXPECT_LT(relative_difference(*((*a.fields).*member), *((*b.fields).*member)), tol);
    }
  std::printf("%s: drag %.12g / %.12g, lift %.12g / %.12g, torque %.12g / %.12g (1 / 2 ranks)\n",
              tag.c_str(), a.means->drag, b.means->drag, a.means->lift, b.means->lift,
              a.means->torque, b.means->torque);
}

/// The case with the direct solver (UMFPACK on one process, MUMPS on two), fields off, and
/// @p extra settings, on one and on two ranks: the same solution.
void expect_two_ranks_match_one(const std::string& tag, const std::string& extra) {
  const TempDir dir(tag);
  std::string log;
  ASSERT_NO_FATAL_FAILURE(run_one_and_two(
      dir, " --quiet --set continuum.linear_solver='\"direct\"' --set output.fields=false" + extra, log));
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
  for (std::size_t p = out2.find("results:"); p != std::string::npos; p = out2.find("results:", p + 1))
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
    for (std::size_t p = text.find("<Piece"); p != std::string::npos; p = text.find("<Piece", p + 1))
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

TEST(FemMpi, LinearisedGravityOnTwoRanksGivesTheOneRankSolution) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  expect_two_ranks_match_one("linearised", " --set scene.gravity=[0.0,-9.81]"
                                           " --set continuum.gravity_treatment='\"linearised\"'");
}

TEST(FemMpi, UnsupportedOptionsOnTwoRanksAreRejectedCleanly) {
  if (!have_mpirun()) GTEST_SKIP() << "no mpirun";
  const TempDir dir("reject");
  struct Refused { const char* set; const char* key; };
  for (const Refused r : {Refused{"continuum.adaptive_cycles=1", "continuum.adaptive_cycles"}}) {
    std::ofstream(dir.path / "case.toml") << fem_case;
    const fs::path out_dir = dir.path / "out";
    std::string out;
    const int rc = run(kMpirun + std::string(GRAINLIFT_BINARY) + " run " +
                           (dir.path / "case.toml").string() + " --solver fem --set " + r.set +
                           " --out " + out_dir.string(),
                       &out);
    std::printf("%s\n", out.c_str());
    EXPECT_EQ(rc, 2) << r.set;  // bad input
    EXPECT_NE(out.find(r.key), std::string::npos) << r.set;
    EXPECT_NE(out.find("one MPI process"), std::string::npos) << r.set;
    EXPECT_FALSE(fs::exists(out_dir / "fem.h5")) << r.set;
  }
}
