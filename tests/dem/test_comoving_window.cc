// The co-moving window (DemSystem::set_window): the band half a box from the intruder pulls
// the grains it passes onto the sites of the bed as it was when the window was set, matching
// grains to the nearest free sites, the sites carried with the bed when it slides.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "grainlift/dem/system/dem_system.h"

namespace gd = grainlift::dem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kD = 0.02;  // m, grain diameter

/// Grains at rest on a lattice, @p columns along x at @p spacing grain diameters (at least
/// 1.25: no two touch), 6 rows 2 d apart at y = 5 to 15 d (the middles of the window's layers,
/// 2 d high), in a box 20 d long, periodic in x; the tests' intruder (radius 0.5 d) moves along
/// x at 1 m/s below them at y = 1 d, touching nothing.
struct Lattice {
  std::vector<gd::Disk> grains;
  gd::SystemOptions options;
  explicit Lattice(int columns = 10, double spacing = 2.0) {
    options.box = {0.0, 20 * kD, 0.0, 16 * kD, true, false};
    options.dt = 1e-5;
    for (int row = 0; row < 6; ++row) {
      for (int col = 0; col < columns; ++col) {
        gd::Disk d;
        d.x = spacing * (col + 0.5) * kD;
        d.y = (5 + 2 * row) * kD;
        d.r = 0.5 * kD;
        d.mass = 20.0 * kPi * d.r * d.r;
        grains.push_back(d);
      }
    }
  }
};

}  // namespace

// Physics: the band's pull on a grain inside it is a spring to its site, a = -s rate^2 (x -
// site) (s = (1 - u^2)^2, the ramp across the band, u = 2 (x - centre) / width), less a
// share of its layer's total pull in proportion to its ramp: a_i -= s_i sum_j m_j a_j /
// sum_j m_j s_j, so that the band pushes no layer as a whole. A lattice dense along x (spacing
// 1.25 d, 16 columns, no two grains touching, one row per layer), at rest, on its sites except one grain of
// row 2 inside the band, displaced by (0.2, 0.1) d. Expected accelerations of the first kick
// (prepare(): the matching, then the pull): the displaced grain's and its row's band grains'
// by the formula above (to 1e-12 relative), the row's total m a zero (to 1e-12 of the
// displaced grain's pull), nothing on the other rows. Its site is the nearest one (the grain's
// own: sites, not identities, are checked by swapping two grains: each is pulled to the
// other's site).
TEST(ComovingWindow, PullIsASpringToTheSiteLessTheLayersRecoil) {
  const Lattice bed(16, 1.25);
  const gd::SystemOptions& o = bed.options;
  const std::vector<gd::Disk>& sites = bed.grains;
  const double v = 1.0, width = 6 * kD, rate = 50 * v / width, centre = 10 * kD;
  const int g = 2 * 16 + 7;  // row 2, x = 9.375 d: inside the band [7, 13] d
  for (bool swapped : {false, true}) {
    SCOPED_TRACE(swapped ? "swapped with its neighbour" : "displaced");
    gd::DemSystem s(o);
    s.set_bodies(sites, {});
    s.set_intruder(0.0, kD, 0.5 * kD, v, 0.0, 0.0, 0.0);
    s.set_window(width, rate, kD);
    std::vector<gd::Disk> moved = sites;
    const double ex = 0.2 * kD, ey = 0.1 * kD;
    moved[g].x += ex;
    moved[g].y += ey;
    if (swapped) {  // g and g + 1 trade places (each then displaced by ex from the other's site)
      moved[g + 1].x = sites[g].x + ex;
      moved[g].x = sites[g + 1].x + ex;
      moved[g + 1].y = sites[g].y + ey;
    }
    s.set_bodies(moved, {});
    s.prepare();
    const gd::ParticleArrays& p = s.particles();
    auto ramp = [&](double x) {
      const double u = 2.0 * (x - centre) / width;
      return std::fabs(u) < 1 ? std::pow(1.0 - u * u, 2) : 0.0;
    };
    double sum_s = 0, fx = 0, fy = 0;
    std::vector<double> pull_x(moved.size(), 0.0), pull_y(moved.size(), 0.0);
    for (int i = 32; i < 48; ++i) {
      sum_s += ramp(moved[i].x);
      // the nearest site: its own, or (swapped) the other's
      const int site = !swapped ? i : i == g ? g + 1 : i == g + 1 ? g : i;
      pull_x[i] = -ramp(moved[i].x) * rate * rate * (moved[i].x - sites[site].x);
      pull_y[i] = -ramp(moved[i].x) * rate * rate * (moved[i].y - sites[site].y);
      fx += pull_x[i];
      fy += pull_y[i];
    }
    double mx = 0, my = 0;
    for (int i = 0; i < s.grains(); ++i) {
      SCOPED_TRACE("grain " + std::to_string(i));
      if (i / 16 != 2) {
        EXPECT_EQ(p.ax[i], 0.0);
        EXPECT_EQ(p.ay[i], 0.0);
        continue;
      }
      const double want_x = pull_x[i] - ramp(moved[i].x) * fx / sum_s;
      const double want_y = pull_y[i] - ramp(moved[i].x) * fy / sum_s;
      EXPECT_NEAR(p.ax[i], want_x, 1e-12 * std::abs(fx) + 1e-300);
      EXPECT_NEAR(p.ay[i], want_y, 1e-12 * std::abs(fy) + 1e-300);
      mx += p.mass[i] * p.ax[i];
      my += p.mass[i] * p.ay[i];
    }
    EXPECT_NEAR(mx, 0.0, 1e-12 * sites[g].mass * std::abs(fx));
    EXPECT_NEAR(my, 0.0, 1e-12 * sites[g].mass * std::abs(fy));
    EXPECT_GT(std::abs(p.ax[g]), 0.1 * ramp(moved[g].x) * rate * rate * ex) << "a real pull";
  }
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

// Physics: the band's contact number (the run's warning that the band stiffens a contact
// network, dem_solver.cc) counts, per grain inside the band, the grains it touches now. Rows of
// grains 0.995 d apart along x (each touches its two neighbours; rows 2 d apart do not touch)
// give exactly 2 inside a band away from the rows' ends; the same rows 1.25 d apart give 0.
TEST(ComovingWindow, BandContactsCountTheTouchingNeighbours) {
  for (double spacing : {0.995, 1.25}) {
    SCOPED_TRACE("spacing " + std::to_string(spacing));
    const Lattice bed(16, spacing);
    gd::DemSystem s(bed.options);
    s.set_bodies(bed.grains, {});
    s.set_intruder(0.0, kD, 0.5 * kD, 1.0, 0.0, 0.0, 0.0);
    s.set_window(6 * kD, 50.0 / (6 * kD), kD);  // band [7, 13] d: rows run 0 to 15.9 d
    s.prepare();
    EXPECT_EQ(s.window_band_contacts(), spacing < 1.0 ? 2.0 : 0.0);
  }
}
