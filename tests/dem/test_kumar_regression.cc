// Reduced Kumar (2019) run: the inverse Magnus effect. A disk of 5 d moving along +x at
// V = 1 m/s and spinning counter-clockwise (Omega = omega R / V = 2) through a 60 d x 40 d bed
// at Phi = 0.8 (walls top and bottom, periodic in x, Kumar's Table I contact law) feels a mean
// lift along -omega x V, i.e. mean F_y < 0 (Kumar Sec. III, Fig. 3), and a positive drag.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "grainlift/dem/scenes/simulation.h"

#include "block_mean.h"

namespace gd = grainlift::dem;
using grainlift::test_support::block_mean;

// Physics: mean lift L = F_y < 0 (along -omega x V) by more than 3 standard errors, and
// mean drag D = -F_x > 0 by more than 3 standard errors. dt = 4e-6 s (0.03 of the collision
// time at the intruder's surface speed) halves the cost of the paper's 2e-6 s; travel 85 d,
// averaged after 5 d (80 d of averaging: the lift is typically 5-6 standard errors below 0).
TEST(KumarRegression, SpinningIntruderFeelsLiftAlongMinusOmegaCrossV) {
  gd::DemConfig c;
  const double d = c.grain_diameter;  // 0.02 m
  c.xmin = -30 * d;
  c.xmax = 30 * d;
  c.ymin = -20 * d;
  c.ymax = 20 * d;
  c.periodic_x = true;
  c.wall_bottom = c.wall_top = true;
  c.area_fraction = 0.8;
  c.intruder_diameter = 5 * d;
  c.intruder_velocity = {1.0, 0.0};
  c.intruder_omega = 2.0 * 1.0 / (2.5 * d);  // Omega = 2
  c.dt = 4e-6;
  c.travel = 85;
  c.steady_travel = 5;
  c.sample_every = 50;
  c.threads = 1;  // small bed: OpenMP fork-join would cost more than it gains on a busy machine
  c.seed = 1;
  const auto t0 = std::chrono::steady_clock::now();
  const gd::DemOutput out = gd::run_simulation(c);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_GT(out.samples.size(), out.steady_start_index + 100);
  const auto lift = block_mean(out, [](const gd::IntruderSample& s) { return s.fy; });
  const auto drag = block_mean(out, [](const gd::IntruderSample& s) { return -s.fx; });
  std::printf(
      "reduced Kumar run: %d grains, Phi = %.4f, %lld steps in %.1f s\n"
      "  drag D = %.3f +- %.3f N/m, lift L = %.3f +- %.3f N/m (block standard errors), L/D = "
      "%.3f\n",
      out.grains, out.achieved_area_fraction, out.steps, seconds, drag.mean, drag.stderr_,
      lift.mean, lift.stderr_, lift.mean / drag.mean);
  RecordProperty("drag", std::to_string(drag.mean));
  RecordProperty("lift", std::to_string(lift.mean));
  EXPECT_LT(lift.mean, -3 * lift.stderr_);
  EXPECT_GT(drag.mean, 3 * drag.stderr_);
  EXPECT_GT(out.contacts.size(), 0u);
}
