// Guillard et al. (2014)'s predictions for a cylinder dragged at depth h under gravity, from
// particles (ctest label `asymptotic`; docs/results-guillard2014.md). The shipped depth-sweep
// case (cases/guillard2014/depth_sweep.toml: their grains and contact law, D = 10 d, 2 D of real
// bed above the intruder and 4 D below, a lid of free-to-rise disks) on a box 8 D wide instead of
// 12 D, 40 d of travel averaged after 10 d, one bed; the depth set by scene.depth_mode and
// scene.depth. The tests run in one process (ctest's GuillardAsymptotic) and share their runs:
// the heavy lid at 4 D is run once for both, three runs of about 50 s on one core in all.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "block_mean.h"
#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/shared/case/case_loader.h"

namespace gd = grainlift::dem;
using grainlift::test_support::block_mean;
using grainlift::test_support::MeanAndError;

namespace {

constexpr double kD = 0.015;  // m, intruder diameter of the case

struct Lift {
  MeanAndError lift;
  double buoyancy = 0;  ///< rho g pi D^2 / 4 with the case's g
};

/// The depth-sweep case at depth h_over_D in @p mode ("heavy_lid" or "lid_only"); each
/// (mode, depth) is run once per process.
Lift run(const std::string& mode, double h_over_D) {
  static std::map<std::pair<std::string, double>, Lift> done;
  const auto key = std::make_pair(mode, h_over_D);
  if (const auto it = done.find(key); it != done.end()) return it->second;
  const grainlift::Case c = grainlift::load_case(
      std::string(GRAINLIFT_SOURCE_DIR) + "/cases/guillard2014/depth_sweep.toml",
      {"scene.depth_mode=\"" + mode + "\"", "scene.depth=" + std::to_string(h_over_D * kD),
       "domain.x_range=[-0.06, 0.06]", "dem.travel=40.0", "dem.steady_travel=10.0",
       "output.fields=false"});
  const gd::DemOutput out = gd::run_simulation(gd::make_dem_config(c, 1));
  Lift l;
  l.lift = block_mean(out, [](const gd::IntruderSample& s) { return s.fy; });
  l.buoyancy = c.bulk_density() * c.reference_gravity() * M_PI * kD * kD / 4;
  std::printf("%s, h = %g D: lift %.4g +- %.2g N/m = %.2f +- %.2f buoyancies\n", mode.c_str(),
              h_over_D, l.lift.mean, l.lift.stderr_, l.lift.mean / l.buoyancy,
              l.lift.stderr_ / l.buoyancy);
  done.emplace(key, l);
  return l;
}

}  // namespace

// Prediction 5 (Guillard 2014, Sec. IV and Fig. 9): without a pressure gradient there is no
// lift. At h = 4 D, the same P0 = rho g h with gravity on the lid only: the lift is within 3
// standard errors of zero and below a third of the lift with the gradient (heavy lid), which is
// itself above zero by more than 3 standard errors. Measured here: 5.92 +- 0.60 buoyancies with
// the gradient, 0.92 +- 0.37 without (docs/results-guillard2014.md, a box 12 D wide with 6 D
// below, 3 beds, 20-60 d of travel: 8.04 +- 0.40 and 0.55 +- 0.27; the lift depends on the box
// and on how much uncrossed bed is left ahead, the drag hardly; without the gradient the lift is
// within 2 errors of zero to 8 D and 4.4 +- 0.9 at 12 D, towards the lid of free disks).
TEST(GuillardAsymptotic, NoLiftWithoutAGradient) {
  const Lift grad = run("heavy_lid", 4), flat = run("lid_only", 4);
  EXPECT_GT(grad.lift.mean, 3 * grad.lift.stderr_);
  EXPECT_LT(std::abs(flat.lift.mean), 3 * flat.lift.stderr_);
  EXPECT_LT(std::abs(flat.lift.mean), grad.lift.mean / 3);
}

// Prediction 6 (Guillard 2014, Fig. 11; appendix B): once deep, the lift in buoyancies does not
// depend on the depth. Heavy lid at h = 4 D and 8 D: L/B agree within 3 combined standard
// errors, and within 40% of the deeper one so that large errors cannot make them agree. Measured
// here: 5.92 +- 0.60 and 5.05 +- 0.96 (the sweep's box, 3 beds, 20-60 d: 8.04 +- 0.40,
// 9.32 +- 0.61, 11.33 +- 0.57 at 4, 6, 8 D; less the no-gradient lift 7.5, 9.4, 10.0). At fixed
// P0 the lift is the no-gradient lift plus the gradient's part, which is consistent with linear
// in g (docs/results-guillard2014.md).
TEST(GuillardAsymptotic, LiftIndependentOfDepthOnceDeep) {
  const Lift h4 = run("heavy_lid", 4), h8 = run("heavy_lid", 8);
  const double l4 = h4.lift.mean / h4.buoyancy, l8 = h8.lift.mean / h8.buoyancy;
  const double err = std::hypot(h4.lift.stderr_ / h4.buoyancy, h8.lift.stderr_ / h8.buoyancy);
  EXPECT_LT(std::abs(l4 - l8), 3 * err);
  EXPECT_LT(std::abs(l4 - l8), 0.4 * l8);
}
