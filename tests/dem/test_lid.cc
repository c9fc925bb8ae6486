// Pressure-controlled lid (lid.h): the top wall moves along y, as one rigid body or disk by disk,
// under a target pressure P, without gravity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/boundaries/lid.h"
#include "grainlift/dem/system/system_setup.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/scenes/simulation.h"
#include "dem_beds.h"

namespace gd = grainlift::dem;

namespace {

/// 30 d x 20 d box of Kumar grains at Phi 0.82, periodic in x, bottom wall and
/// a lid on top, no gravity.
gd::DemConfig lid_case(double pressure) {
  gd::DemConfig c = grainlift::test_support::walled_bed(30, 20, 0.82);
  c.dt = 4e-6;
  c.seed = 7;
  c.lid_pressure = pressure;
  return c;
}

/// Mean contact stress sigma_yy (N/m, compressive positive) of everything between the bottom
/// wall's centres and the lid's: (1 / A) sum over contacts of f_y l_y, f the force on the grain,
/// l the branch vector from the partner's centre to the grain's (Kumar eq. A8 form).
double mean_contact_stress_yy(const gd::DemSystem& s, double area) {
  const auto& nl = s.neighbors();
  const auto& p = s.particles();
  double sum = 0;
  for (int i = 0; i < s.grains(); ++i) {
    for (std::int64_t k = nl.first[i]; k < nl.first[i + 1]; ++k) {
      const int j = nl.partner[k];
      double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j];
      s.box().min_image(dx, dy);
      sum += nl.fy[k] * dy;
    }
  }
  return sum / area;
}

/// Settles a lid bed (150,000 steps by default: ~25 periods of the lid critically damped on the
/// bed's estimated stiffness, lid mass = bed mass; at 60,000 one bed of five, seeds 7-11, was
/// still sinking: 466 N/m, drift 0.02 d, where 150,000 settle all five to 500.0 N/m within
/// 1e-6 d), then averages over the next 20,000 steps.
struct LidRun {
  double y0 = 0, y_start = 0, y_end = 0;  ///< lid height: made, settled, end
  double pressure = 0;                     ///< time-averaged force on the lid / width
  double sigma_yy = 0;                     ///< the bed's contact stress over 20 snapshots
  double disk_spread = 0;                  ///< highest - lowest lid disk at the end
};

LidRun settle_and_average(const gd::DemConfig& c, long settle = 150000) {
  const double d = c.grain_diameter;
  const gd::PackedBed bed = gd::prepare_packing(c);
  const auto system = gd::system_on_bed(c, bed);
  gd::DemSystem& s = *system;
  s.attach_lid(gd::PressureLid(c, s));
  const gd::PressureLid& lid = *s.lid();
  LidRun r;
  r.y0 = lid.state().y;
  const long average = 20000;
  for (long k = 0; k < settle; ++k) s.step();
  r.y_start = lid.state().y;
  double sigma_sum = 0;
  int snapshots = 0;
  const double y_bottom = c.ymin + 0.5 * d;
  for (long k = 0; k < average; ++k) {
    s.step();
    r.pressure += lid.state().pressure / average;
    if (k % 1000 == 999) {
      sigma_sum += mean_contact_stress_yy(s, (c.xmax - c.xmin) * (lid.state().y - y_bottom));
      ++snapshots;
    }
  }
  r.y_end = lid.state().y;
  r.sigma_yy = sigma_sum / snapshots;
  double lo = 1e300, hi = -1e300;
  for (int j = lid.begin(); j < lid.end(); ++j) {
    lo = std::min(lo, s.particles().y[j]);
    hi = std::max(hi, s.particles().y[j]);
  }
  r.disk_spread = hi - lo;
  return r;
}

/// The lid compressed the bed (down by more than 0.05 d), carries P within 2% on average, has
/// stopped (drift below 5e-3 d) and the bed's sigma_yy is P within 5%.
void expect_settled_at(const LidRun& r, double pressure, double d) {
  EXPECT_LT(r.y_end, r.y0 - 0.05 * d) << "the lid did not compress the bed";
  EXPECT_NEAR(r.pressure, pressure, 0.02 * pressure);
  EXPECT_LT(std::abs(r.y_end - r.y_start), 5e-3 * d);
  EXPECT_NEAR(r.sigma_yy, pressure, 0.05 * pressure);
}

}  // namespace

// Physics: a bed confined by a lid at pressure P (no gravity, no intruder) settles where the
// grains push the lid back with P. Over the 20,000 steps after settling:
//  * the time-averaged force of the grains on the lid over the width equals P within 2%;
//  * the lid has stopped: drift below 5e-3 d (the last rearrangements of the bed);
//  * the bed's mean contact stress sigma_yy (virial of all contacts between the bottom wall's
//    centres and the lid's, averaged over 20 snapshots) equals P within 5%.
// P = 500 N/m compresses contacts by ~1e-3 d (Kumar's Kn = 2 GPa); the bed, prepared between
// fixed walls at Phi 0.82 and barely loaded, densifies: the lid moves down by more than 0.05 d.
// The rigid lid keeps its disks level (spread below 1e-12 d).
TEST(PressureLid, MeanLidPressureAndBedStressEqualTheTarget) {
  const double pressure = 500.0;
  const auto c = lid_case(pressure);
  const double d = c.grain_diameter;
  const LidRun r = settle_and_average(c);
  expect_settled_at(r, pressure, d);
  EXPECT_LT(r.disk_spread, 1e-12 * d);
}

// The same bed under a lid of free disks (DemConfig::lid_free_disks, Guillard 2014's heavy lid):
// each disk carries its share P W / N, so the same averages hold (lid pressure within 2%, bed
// sigma_yy within 5%, mean height drift below 5e-3 d) after a longer settling, 200,000 steps (at
// 60,000 the disks were still sinking into the pockets of the surface: 474 N/m, drift 0.016 d),
// and the disks settle each on its own
// column of the bed: their heights differ by more than 1e-3 d.
TEST(PressureLid, FreeDiskLidCarriesTheSamePressure) {
  const double pressure = 500.0;
  auto c = lid_case(pressure);
  c.lid_free_disks = true;
  const double d = c.grain_diameter;
  const LidRun r = settle_and_average(c, 200000);
  expect_settled_at(r, pressure, d);
  EXPECT_GT(r.disk_spread, 1e-3 * d);
}

// validate_config refuses a lid without a top wall (naming the reason) and a negative pressure.
TEST(PressureLid, BadSetupsAreRefused) {
  auto c = lid_case(500.0);
  c.wall_top = false;
  try {
    gd::validate_config(c);
    FAIL() << "a lid without a top wall was accepted";
  } catch (const gd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("needs a top wall"), std::string::npos) << e.what();
  }
  c = lid_case(-1.0);
  EXPECT_THROW(gd::validate_config(c), gd::ConfigError);
}
