// The co-moving window (DemSystem::set_window): the band half a box from the intruder pulls
// the grains it passes onto the sites of the bed as it was when the window was set, matching
// grains to the nearest free sites, and leaves free a grain with no site near it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "grainlift/dem/dem_system.h"

namespace gd = grainlift::dem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kD = 0.02;  // m, grain diameter

/// Grains on a square lattice of spacing 2 d (no two touch), 10 columns by 6 rows at y = 4 to
/// 14 d, in a box 20 d long, periodic in x; the intruder (radius 0.5 d) moves along x at 1 m/s
/// below them at y = 1 d, touching nothing.
struct Lattice {
  std::vector<gd::Disk> grains;
  gd::SystemOptions options;
  Lattice() {
    options.box = {0.0, 20 * kD, 0.0, 16 * kD, true, false};
    options.dt = 1e-5;
    for (int row = 0; row < 6; ++row) {
      for (int col = 0; col < 10; ++col) {
        gd::Disk d;
        d.x = (2 * col + 1) * kD;
        d.y = (4 + 2 * row) * kD;
        d.r = 0.5 * kD;
        d.mass = 20.0 * kPi * d.r * d.r;
        grains.push_back(d);
      }
    }
  }
};

}  // namespace

// Physics: inside the band a grain feels a critically damped spring to its site whose rate
// ramps from zero at the band's edges (rate 50 |V| / width: the band passes a grain in 50
// relaxation times at its middle), the sites carried with the bed's median displacement, so a
// grain the band has passed sits on a site, at rest. The bed found by the band: every grain
// shifted by (0.3, 0.1) d from the set-up bed, one row also jittered by up to 0.4 d, two
// neighbours swapped, one grain lifted 1.2 d above the top row (1.2 d from every site, beyond
// the match radius of 1 d, like a grain in the hole the intruder left). Expected: every grain
// on its site + (0.3, 0.1) d (the medians ignore the few outliers), the swapped pair each on
// the other's site (sites, not identities), the lifted grain where it was (no site; it starts
// at rest and only its spin is damped). The grains start at rest (spins aside); a box length
// and a band width of travel (the band sweeps over every grain). Tolerances: 1e-6 d from the
// site (the relaxation leaves exp(-50 x 0.6) or less), 1e-9 d for the lifted grain.
TEST(ComovingWindow, BandPullsTheGrainsItPassesOntoTheNearestSites) {
  Lattice bed;
  gd::DemSystem s(bed.options);
  s.set_bodies(bed.grains, {});
  const double v = 1.0, width = 6 * kD;
  s.set_intruder(0.0, kD, 0.5 * kD, v, 0.0, 0.0, 0.0);
  s.set_window(width, 50 * v / width, kD);
  const double sx = 0.3 * kD, sy = 0.1 * kD;
  std::vector<gd::Disk> moved = bed.grains;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < moved.size(); ++i) {
    moved[i].x += sx;
    moved[i].y += sy;
    moved[i].w = 10 * u(rng);  // at rest otherwise: nothing moves before the band arrives
    if (i / 10 == 1) {         // row 1 jittered
      const double a = kPi * u(rng), len = 0.4 * kD * std::abs(u(rng));
      moved[i].x += len * std::cos(a);
      moved[i].y += len * std::sin(a);
    }
  }
  const int a = 25, b = 26;  // row 2, neighbours along x
  moved[a].x = bed.grains[b].x + sx;
  moved[b].x = bed.grains[a].x + sx;
  const int lone = 53;  // top row, lifted
  moved[lone].y += 1.2 * kD;
  moved[lone].w = 0;
  s.set_bodies(moved, {});  // the same number of grains: the window keeps its sites
  // a box length and a band width: the band passes wholly over every grain, including those
  // it covered at the start
  const long long steps = std::llround((20 * kD + width) / (v * bed.options.dt)) + 100;
  s.advance(steps);
  const gd::ParticleArrays& p = s.particles();
  EXPECT_EQ(s.intruder_touching(), 0);
  for (int i = 0; i < s.grains(); ++i) {
    SCOPED_TRACE("grain " + std::to_string(i));
    if (i == lone) {
      EXPECT_NEAR(p.x[i], moved[lone].x, 1e-9 * kD);
      EXPECT_NEAR(p.y[i], moved[lone].y, 1e-9 * kD);
      continue;
    }
    const int site = i == a ? b : i == b ? a : i;
    EXPECT_NEAR(p.x[i], bed.grains[site].x + sx, 1e-6 * kD);
    EXPECT_NEAR(p.y[i], bed.grains[site].y + sy, 1e-6 * kD);
    EXPECT_NEAR(std::hypot(p.vx[i], p.vy[i]), 0.0, 1e-6 * v);
    EXPECT_NEAR(p.w[i] * p.r[i], 0.0, 1e-6 * v);
  }
  const gd::DemSystem::WindowStats st = s.window_stats();
  EXPECT_GT(st.builds, 0);
  EXPECT_LT(st.matched_fraction, 1.0);  // the lifted grain, while in the band
}

// Physics: the band restores the bed's structure without holding the bed: a bed sliding along
// the box as a whole (every grain at 0.3 |V| along x, on the lattice it was set up on) keeps
// sliding through the band, unslowed, over a box length and a band width of travel: every
// velocity 0.3 |V| to 1e-9 |V| and every grain where the slide took it to 1e-6 d (the sites
// follow the slide one matching behind, extrapolated with the median velocity). (Sites held
// in place stopped such a bed: on the reduced Kumar bed they tripled the drag.)
TEST(ComovingWindow, BandLetsASlidingBedSlide) {
  Lattice bed;
  const double v = 1.0, width = 6 * kD, u = 0.3 * v;
  for (auto& g : bed.grains) g.vx = u;
  gd::DemSystem s(bed.options);
  s.set_bodies(bed.grains, {});
  s.set_intruder(0.0, kD, 0.5 * kD, v, 0.0, 0.0, 0.0);
  s.set_window(width, 50 * v / width, kD);
  const long long steps = std::llround((20 * kD + width) / (v * bed.options.dt)) + 100;
  s.advance(steps);
  const gd::ParticleArrays& p = s.particles();
  const double lx = 20 * kD, slide = u * bed.options.dt * static_cast<double>(steps);
  for (int i = 0; i < s.grains(); ++i) {
    SCOPED_TRACE("grain " + std::to_string(i));
    EXPECT_NEAR(p.vx[i], u, 1e-9 * v);
    EXPECT_NEAR(p.vy[i], 0.0, 1e-9 * v);
    const double x = std::fmod(bed.grains[i].x + slide, lx);
    EXPECT_NEAR(std::remainder(p.x[i] - x, lx), 0.0, 1e-6 * kD);
    EXPECT_NEAR(p.y[i], bed.grains[i].y, 1e-6 * kD);
  }
  EXPECT_GT(s.window_stats().band_grains, 5.0);
}

// Physics: none; width 0 turns the window off: not a bit of the run changes.
TEST(ComovingWindow, WidthZeroChangesNothing) {
  Lattice bed;
  for (auto& g : bed.grains) g.vx = 0.5;
  gd::DemSystem s0(bed.options), s1(bed.options);
  for (gd::DemSystem* s : {&s0, &s1}) {
    s->set_bodies(bed.grains, {});
    s->set_intruder(0.0, 2 * kD, kD, 1.0, 0.0, 0.0, 0.0);
  }
  s1.set_window(0.0, 1.0, kD);
  s0.advance(2000);
  s1.advance(2000);
  for (int i = 0; i < s0.grains(); ++i) {
    ASSERT_EQ(s0.particles().x[i], s1.particles().x[i]);
    ASSERT_EQ(s0.particles().vx[i], s1.particles().vx[i]);
  }
  EXPECT_EQ(s1.window_stats().builds, 0);
}
