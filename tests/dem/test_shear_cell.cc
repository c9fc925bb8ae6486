// DEM simple-shear cell (shear_cell.h): Kumar grains between rough walls, the lid at P = 500 N/m
// (kn / P = 8e4, nearly rigid grains) moved along x at U, without gravity and with it (the
// creeping-layer cell of `grainlift calibrate --nonlocal`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "grainlift/dem/scenes/shear_cell.h"
#include "grainlift/shared/statistics/statistics.h"

namespace gd = grainlift::dem;

namespace {

constexpr double kPressure = 500;  // N/m

/// A 20 d x 16 d cell at the target inertial number I (U = I H sqrt(P / rho_s) / d, H between
/// the walls' centre lines), run-in and window given as shear strains of U / H.
gd::ShearCellConfig cell(double inertial_number, double friction, double strain_in,
                         double strain_window) {
  gd::ShearCellConfig c;
  c.grains.dt = 4e-6;
  c.grains.seed = 5;
  c.grains.contact.friction = friction;
  c.width = 20;
  c.height = 16;
  c.pressure = kPressure;
  const double d = c.grains.grain_diameter, gap = (c.height - 1) * d;
  c.wall_speed = inertial_number * gap * std::sqrt(kPressure / c.grains.density) / d;
  const double rate = c.wall_speed / gap;
  c.run_in_steps = static_cast<long long>(strain_in / (rate * c.grains.dt));
  c.measure_steps = static_cast<long long>(strain_window / (rate * c.grains.dt));
  c.max_run_in_steps = c.run_in_steps + 2 * c.measure_steps;
  c.sample_every = 20;
  return c;
}

/// One sheared cell at I ~ 0.1 shared by the tests that read it (strain 8 run-in: the heavy,
/// critically damped lid creeps while the bed dilates; window 4).
const gd::ShearCellResult& sheared() {
  static const gd::ShearCellResult r = gd::run_shear_cell(cell(0.1, 0.5, 8, 4));
  return r;
}

}  // namespace

// Physics: in steady simple shear the shear stress is uniform across the height (the grains'
// x momentum changes only by the two walls' forces, and its time average is stationary), so over
// the same window the shear force of the grains on the top wall equals minus that on the bottom
// wall: tau_top = tau_bottom within 3 combined block standard errors.
TEST(ShearCell, TopAndBottomWallsCarryTheSameShearStress) {
  const auto& r = sheared();
  EXPECT_TRUE(r.steady);
  EXPECT_GT(r.shear_stress.mean, 0.1 * kPressure) << "the cell is not sheared";
  EXPECT_NEAR(r.shear_stress.mean, r.bottom_shear_stress.mean,
              3 * std::hypot(r.shear_stress.se, r.bottom_shear_stress.se))
      << "top " << r.shear_stress.mean << " +- " << r.shear_stress.se << ", bottom "
      << r.bottom_shear_stress.mean << " +- " << r.bottom_shear_stress.se << " N/m";
}

// Physics: in the bulk of simple shear (away from the walls' layers of 3 d) the mean velocity
// is linear in y (GDR MiDi 2004, plane shear); at I ~ 0.1 the least-squares line through the
// bins of one d explains it with R^2 > 0.95, and the measured I is within a factor 2 of the
// target (the rest is slip at the walls).
TEST(ShearCell, BulkVelocityProfileIsLinear) {
  const auto& r = sheared();
  EXPECT_GE(r.bulk_bins, 5);
  EXPECT_GT(r.profile_r2, 0.95) << "largest deviation " << r.profile_max_deviation << " U";
  EXPECT_GT(r.inertial_number, 0.05);
  EXPECT_LT(r.inertial_number, 0.2);
}

// Physics: without shear (U = 0) there is no preferred direction along x, so the mean shear
// stress vanishes. A single jammed frictional packing is static and keeps the residual shear
// stress of its preparation (|tau| up to mu_s P, of either sign; measured -44 +- 1 N/m for one
// seed), so the zero mean is that of the ensemble: over 6 beds (seeds) the mean of the lids'
// window-averaged tau is zero within 3 standard errors of that mean (the spread of the beds),
// and every lid pressure is P within 2% (60,000 steps of run-in let the lid close the gap of a
// bed prepared at Phi 0.8 between fixed walls).
TEST(ShearCell, NoShearNoMeanShearStress) {
  std::vector<double> tau, tau_se;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    gd::ShearCellConfig c = cell(0.1, 0.5, 0, 0);
    c.grains.seed = seed;
    c.wall_speed = 0;
    c.run_in_steps = 60000;
    c.measure_steps = 20000;
    c.max_run_in_steps = c.run_in_steps;
    const gd::ShearCellResult r = gd::run_shear_cell(c);
    tau.push_back(r.shear_stress.mean);
    tau_se.push_back(r.shear_stress.se);
    EXPECT_NEAR(r.pressure.mean, kPressure, 0.02 * kPressure) << "seed " << seed;
  }
  const grainlift::PooledMean m = grainlift::pooled_mean(tau, tau_se);
  EXPECT_NEAR(m.mean, 0.0, 3 * m.error) << m.mean << " +- " << m.error << " N/m over 6 beds";
}

// Physics: the quasi-static friction coefficient of a granular packing comes mostly from the
// grains' sliding friction; da Cruz et al. 2005 (2D disks) find mu_s ~ 0.26 with mu_p = 0.4 and
// ~0.1 without. At the same small I ~ 0.01 frictionless grains (mu = 0) give a smaller
// mu = tau / P than frictional ones (mu = 0.5), by more than 3 combined standard errors.
TEST(ShearCell, FrictionlessGrainsHaveSmallerMacroscopicFriction) {
  const gd::ShearCellResult smooth = gd::run_shear_cell(cell(0.01, 0.0, 1, 2));
  const gd::ShearCellResult rough = gd::run_shear_cell(cell(0.01, 0.5, 1, 2));
  EXPECT_LT(smooth.friction.mean + 3 * std::hypot(smooth.friction.se, rough.friction.se),
            rough.friction.mean)
      << "mu = 0: " << smooth.friction.mean << " +- " << smooth.friction.se << " (I "
      << smooth.inertial_number << "), mu = 0.5: " << rough.friction.mean << " +- "
      << rough.friction.se << " (I " << rough.inertial_number << ")";
}

// Physics: with gravity across the layer (the creeping-layer cell) the grains' vertical momentum
// is stationary, so the bottom wall carries the lid's load plus the grains' whole weight:
// p_bottom = P_lid + g M / W within 3 combined block errors (here g M / W = 2 P); the shear stress
// is still uniform (gravity has no x component): tau_top = tau_bottom within 3 errors; and the
// pressure grows downwards, so mu = tau / p falls below the sheared top's and the flow is
// confined there: the lowest bulk bin moves at less than 2% of the lid's speed and 10 times
// slower than the highest (measured 0.3% and 39 times). (Lid at I ~ 0.1 of the whole gap, 30
// strains of run-in, window 4.)
TEST(ShearCell, GravityLoadsTheBottomWallAndConfinesTheFlowToTheTop) {
  gd::ShearCellConfig c = cell(0.1, 0.5, 30, 4);
  const double d = c.grains.grain_diameter;
  c.gravity = 2 * kPressure / (c.grains.density * 0.8 * (c.height - 1) * d);
  const gd::ShearCellResult r = gd::run_shear_cell(c);
  const double width = c.width * d, weight = c.gravity * r.grain_mass / width;
  EXPECT_GT(weight, 1.6 * kPressure);
  EXPECT_NEAR(r.bottom_pressure.mean, r.pressure.mean + weight,
              3 * std::hypot(r.bottom_pressure.se, r.pressure.se))
      << "bottom " << r.bottom_pressure.mean << " +- " << r.bottom_pressure.se << ", lid "
      << r.pressure.mean << " +- " << r.pressure.se << ", weight " << weight << " N/m";
  EXPECT_NEAR(r.shear_stress.mean, r.bottom_shear_stress.mean,
              3 * std::hypot(r.shear_stress.se, r.bottom_shear_stress.se));
  double low = -1, high = -1;  // the lowest and highest bulk bins' velocity
  for (std::size_t k = 0; k < r.profile_y.size(); ++k) {
    if (r.profile_y[k] < 3 * d || r.profile_y[k] > r.lid_height.mean - 3 * d) continue;
    if (low < 0) low = r.profile_vx[k];
    high = r.profile_vx[k];
  }
  EXPECT_LT(std::abs(low), 0.02 * c.wall_speed) << low << " m/s";
  EXPECT_GT(high, 10 * std::abs(low)) << high << " m/s, lowest " << low;
  EXPECT_GT(r.profile_pressure.front(), r.profile_pressure.back() + 0.5 * weight);
}
