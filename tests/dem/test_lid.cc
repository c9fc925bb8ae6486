// Pressure-controlled lid (lid.h): the top wall moves as a rigid body along y under a target
// pressure P, without gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "grainlift/dem/dem_system.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/lid.h"
#include "grainlift/dem/system_setup.h"
#include "grainlift/dem/packing.h"
#include "grainlift/dem/simulation.h"
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

}  // namespace

// Physics: a bed confined by a lid at pressure P (no gravity, no intruder) settles where the
// grains push the lid back with P. After settling (60,000 steps: the lid critically damped on the
// bed's estimated stiffness, lid mass = bed mass), over the next 20,000 steps:
//  * the time-averaged force of the grains on the lid over the width equals P within 2%;
//  * the lid has stopped: drift below 5e-3 d (the last rearrangements of the bed);
//  * the bed's mean contact stress sigma_yy (virial of all contacts between the bottom wall's
//    centres and the lid's, averaged over 20 snapshots) equals P within 5%.
// P = 500 N/m compresses contacts by ~1e-3 d (Kumar's Kn = 2 GPa); the bed, prepared between
// fixed walls at Phi 0.82 and barely loaded, densifies: the lid moves down by more than 0.05 d.
TEST(PressureLid, MeanLidPressureAndBedStressEqualTheTarget) {
  const double pressure = 500.0;
  const auto c = lid_case(pressure);
  const double d = c.grain_diameter;
  const gd::PackedBed bed = gd::prepare_packing(c);
  const auto system = gd::system_on_bed(c, bed);
  gd::DemSystem& s = *system;
  s.attach_lid(gd::PressureLid(c, s));
  const gd::PressureLid& lid = *s.lid();
  const double y0 = lid.state().y;
  // settling: ~10 periods of the lid on the bed's estimated stiffness
  const long settle = 60000, average = 20000;
  for (long k = 0; k < settle; ++k) {
    s.step();
  }
  const double y_start = lid.state().y;
  double p_sum = 0, sigma_sum = 0;
  int snapshots = 0;
  const double y_bottom = c.ymin + 0.5 * d;
  for (long k = 0; k < average; ++k) {
    s.step();
    p_sum += lid.state().pressure;
    if (k % 1000 == 999) {
      sigma_sum += mean_contact_stress_yy(s, (c.xmax - c.xmin) * (lid.state().y - y_bottom));
      ++snapshots;
    }
  }
  const double y_end = lid.state().y;
  EXPECT_LT(y_end, y0 - 0.05 * d) << "the lid did not compress the bed";
  EXPECT_NEAR(p_sum / average, pressure, 0.02 * pressure);
  EXPECT_LT(std::abs(y_end - y_start), 5e-3 * d);
  EXPECT_NEAR(sigma_sum / snapshots, pressure, 0.05 * pressure);
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
