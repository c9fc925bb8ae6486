// The continuum solver under `mpirun -np 2`: the distributed solve is not implemented yet, so
// every rank must stop with bad input (exit 2) and a message that says so, before any rank
// solves or writes a file. Skipped when mpirun is not installed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "run_command.h"

namespace fs = std::filesystem;

namespace {

int run(const std::string& command, std::string* output) {
  const grainlift::test_support::CommandOutcome o = grainlift::test_support::run_command(command);
  if (output) *output = o.output;
  return o.code;
}

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
refinement = 0
linear_solver = "amg"
[output]
fields = false
)";

}  // namespace

TEST(FemMpi, TwoRanksAreRejectedCleanly) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun";
  const fs::path dir = fs::temp_directory_path() / ("grainlift_fem_mpi_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << fem_case;
  std::string out;
  const int rc = run("mpirun --allow-run-as-root --oversubscribe -np 2 " +
                         std::string(GRAINLIFT_BINARY) + " run " + (dir / "case.toml").string() +
                         " --solver fem --out " + (dir / "out").string(),
                     &out);
  std::printf("%s\n", out.c_str());
  EXPECT_NE(rc, 0);
  EXPECT_NE(out.find("one MPI process"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out" / "fem.h5"));
  // the same case on one process runs
  const int rc1 = run(std::string(GRAINLIFT_BINARY) + " run " + (dir / "case.toml").string() +
                          " --solver fem --quiet --out " + (dir / "out1").string(),
                      &out);
  EXPECT_EQ(rc1, 0) << out;
  EXPECT_TRUE(fs::exists(dir / "out1" / "fem.h5"));
  fs::remove_all(dir);
}
