// The command loads the continuum (deal.II and its ~200 libraries) only when a run solves the
// continuum (apps/src/fem_module_loader.h). Expected: `validate` and a DEM run never open
// libdeal.ii (the dynamic linker's own log, LD_DEBUG=libs, names every library it opens); a
// continuum run opens it and solves (a drag that resists the motion).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>

#include "grainlift/shared/results/result_file.h"
#include "run_command.h"
#include "tiny_dem_case.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

const std::string kDealII = "libdeal.ii";

test_support::CommandOutcome traced(const std::string& args) {
  return test_support::run_command("LD_DEBUG=libs " + std::string(GRAINLIFT_BINARY) + " " + args);
}

fs::path scratch() {
  fs::path d = fs::temp_directory_path() / ("grainlift_fem_module_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(FemModule, OnlyAContinuumRunLoadsDealII) {
  const fs::path d = scratch();
  std::ofstream(d / "tiny.toml") << test_support::tiny_case;
  const std::string demo = std::string(GRAINLIFT_SOURCE_DIR) + "/cases/demo/demo.toml";

  const auto validate = traced("validate " + demo);
  ASSERT_EQ(validate.code, 0) << validate.output;
  EXPECT_EQ(validate.output.find(kDealII), std::string::npos) << "validate opened deal.II";

  const auto dem = traced("run " + (d / "tiny.toml").string() + " --solver dem --quiet --out " +
                          (d / "dem").string());
  ASSERT_EQ(dem.code, 0) << dem.output;
  EXPECT_EQ(dem.output.find(kDealII), std::string::npos) << "a DEM run opened deal.II";

  // the control: the same log names deal.II when the continuum runs (the demo at the coarsest
  // level), so the absence above is not a log that names nothing
  const auto fem = traced("run " + demo +
                          " --solver fem --quiet --set continuum.target_error=0 --set "
                          "continuum.refinement=0 --out " + (d / "fem").string());
  ASSERT_EQ(fem.code, 0) << fem.output.substr(fem.output.size() - std::min<std::size_t>(
                               fem.output.size(), 4000));
  EXPECT_NE(fem.output.find(kDealII), std::string::npos);
  const RunResult r = read_result((d / "fem" / "fem.h5").string());
  ASSERT_TRUE(r.means);
  EXPECT_GT(r.means->drag, 0.0);  // the intruder is pushed back by the medium it moves through
  fs::remove_all(d);
}
