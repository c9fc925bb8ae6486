// The bed fingerprint (bed_fingerprint.h) on beds whose structure is known by construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "grainlift/dem/bed/bed_fingerprint.h"
#include "grainlift/dem/bed/packing.h"
#include "dem_beds.h"

using namespace grainlift::dem;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A periodic box (x and y) of side n d with no walls and an intruder of diameter 0 far away.
DemConfig periodic_box(int n, double d) {
  DemConfig c;
  c.xmin = 0;
  c.xmax = n * d;
  c.ymin = 0;
  c.ymax = n * d;
  c.periodic_x = c.periodic_y = true;
  c.wall_bottom = c.wall_top = c.wall_left = c.wall_right = false;
  c.grain_diameter = d;
  c.intruder_diameter = 0;
  return c;
}

}  // namespace

// A square lattice of disks of diameter d at spacing d (1 - 1e-4), periodic both ways: every
// disk touches its 4 neighbours (Z = 4, no rattler), the contact normals lie along x and y in
// equal numbers (fabric xx = yy = 1/2, xy = 0), every nearest gap is -1e-4 d (the first bin,
// [-0.05, 0) d), and each band holds pi/4 / (1 - 1e-4)^2 of its area. Tolerances: rounding.
TEST(BedFingerprint, SquareLatticeHasFourContactsAndAnIsotropicFabric) {
  const double d = 0.01, a = d * (1 - 1e-4);
  const int n = 20;
  DemConfig c = periodic_box(n, a);  // bands of one lattice spacing
  PackedBed bed;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      bed.x.push_back((i + 0.5) * a);
      bed.y.push_back((j + 0.5) * a);
      bed.r.push_back(0.5 * d);
    }
  const BedFingerprint f = bed_fingerprint(c, bed, {});
  EXPECT_NEAR(f.contacts_per_grain, 4.0, 1e-12);
  EXPECT_NEAR(f.rattler_fraction, 0.0, 1e-12);
  EXPECT_NEAR(f.fabric_xx, 0.5, 1e-9);
  EXPECT_NEAR(f.fabric_yy, 0.5, 1e-9);
  EXPECT_NEAR(f.fabric_xy, 0.0, 1e-9);
  ASSERT_EQ(f.gap_fraction.size() + 1, f.gap_edges.size());
  EXPECT_NEAR(f.gap_fraction[0], 1.0, 1e-12);
  EXPECT_NEAR(f.mean_gap, -1e-4 * d / a, 1e-12);
  ASSERT_FALSE(f.band_area_fraction.empty());
  EXPECT_EQ(f.band_area_fraction.size(), std::size_t(n));
  for (double phi : f.band_area_fraction) EXPECT_NEAR(phi, kPi / 4 / std::pow(1 - 1e-4, 2), 1e-3);
  EXPECT_TRUE(f.ring_r.empty());  // no intruder
}

// The same lattice pulled apart along x (spacing 1.2 d in x, d (1 - 1e-4) in y): only the
// vertical contacts remain (Z = 2, fabric yy = 1), the nearest gap is the vertical one; with
// the spacing also 1.2 d in y no disk touches (Z = 0, all rattlers) and every nearest gap is
// 0.2 d (the bin [0.1, 0.3) d).
TEST(BedFingerprint, AnisotropicAndLooseLattices) {
  const double d = 0.01;
  const int n = 12;
  for (const double ay : {d * (1 - 1e-4), 1.2 * d}) {
    DemConfig c = periodic_box(n, d);
    c.xmax = n * 1.2 * d;
    c.ymax = n * ay;
    PackedBed bed;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        bed.x.push_back((i + 0.5) * 1.2 * d);
        bed.y.push_back((j + 0.5) * ay);
        bed.r.push_back(0.5 * d);
      }
    const BedFingerprint f = bed_fingerprint(c, bed, {});
    if (ay < d) {
      EXPECT_NEAR(f.contacts_per_grain, 2.0, 1e-12);
      EXPECT_NEAR(f.rattler_fraction, 0.0, 1e-12);
      EXPECT_NEAR(f.fabric_yy, 1.0, 1e-9);
      EXPECT_NEAR(f.fabric_xx, 0.0, 1e-9);
    } else {
      EXPECT_EQ(f.contacts_per_grain, 0.0);
      EXPECT_EQ(f.rattler_fraction, 1.0);
      EXPECT_NEAR(f.mean_gap, 0.2, 1e-9);
      EXPECT_NEAR(f.gap_fraction[6], 1.0, 1e-12);  // [0.1, 0.3) d
    }
  }
}

// Around an intruder at the centre of a uniform lattice the rings see the lattice's area
// fraction (each ring within 20%, their mean within 3%: centre binning, below); a lattice with the
// disks within 2 d of the intruder removed shows an empty first two rings and the full value beyond
// 3 d.
TEST(BedFingerprint, RingsAroundTheIntruderSeeAHole) {
  const double d = 0.01;
  const int n = 40;
  DemConfig c = periodic_box(n, d);
  c.intruder_diameter = 6 * d;
  c.intruder_position = {0.5 * n * d, 0.5 * n * d};
  PackedBed full, holed;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) * d, y = (j + 0.5) * d;
      const double r = std::hypot(x - 0.5 * n * d, y - 0.5 * n * d);
      if (r < 3 * d + 0.5 * d) continue;  // outside the intruder in both
      full.x.push_back(x), full.y.push_back(y), full.r.push_back(0.5 * d);
      if (r < 3 * d + 2 * d) continue;
      holed.x.push_back(x), holed.y.push_back(y), holed.r.push_back(0.5 * d);
    }
  const BedFingerprint f = bed_fingerprint(c, full, {});
  const BedFingerprint h = bed_fingerprint(c, holed, {});
  ASSERT_EQ(f.ring_r.size(), 10u);
  // centre binning in rings one lattice spacing wide: each ring holds a whole number of disks
  // whose centres the lattice places unevenly (measured 0.70-0.92 for pi/4 = 0.785); the
  // area-weighted mean over rings 3-9 averages that out
  double grains = 0, area = 0;
  for (std::size_t q = 3; q < 10; ++q) {
    EXPECT_NEAR(f.ring_area_fraction[q], kPi / 4, 0.2 * kPi / 4);
    grains += f.ring_area_fraction[q] * f.ring_r[q];
    area += f.ring_r[q];
  }
  EXPECT_NEAR(grains / area, kPi / 4, 0.03 * kPi / 4);
  EXPECT_EQ(h.ring_area_fraction[0], 0.0);
  EXPECT_EQ(h.ring_area_fraction[1], 0.0);
  for (std::size_t q = 3; q < 10; ++q)
    EXPECT_NEAR(h.ring_area_fraction[q], f.ring_area_fraction[q], 1e-12);
}

// Kumar's wall compression (DemConfig::preparation = wall_compression) of a walled box to Phi
// 0.8, below jamming, where nothing evens the density out once the walls stop. Under the
// relaxation's background drag (1/(2000 dt), the default) a grain pushed by a wall stops
// within ~v/rate, about 1 mm: the walls build dense layers and the centre line keeps about the
// insertion's area fraction (0.45). With contact damping only, the pushed grains carry the
// compression inwards. Expected: both beds at the target area fraction (within 1%), and the
// drag-free bed's centre (the four bands round the intruder's height) denser by at least 0.05
// and its band-to-band spread smaller (in the reduced Kumar box: centre 0.50-0.61 against
// 0.67-0.74, spread 0.11 against 0.06; docs/results-kumar2019.md section 7).
TEST(BedFingerprint, WallCompressionWithoutDragLeavesALessDepletedCentre) {
  double centre[2] = {0, 0}, spread[2] = {0, 0};
  for (int drag = 0; drag < 2; ++drag) {
    DemConfig c = grainlift::test_support::walled_bed(30, 24, 0.8);
    c.preparation = Preparation::wall_compression;
    c.compression_drag = drag == 1;
    c.packing_cache_dir = "";
    const PackedBed bed = prepare_packing(c);
    EXPECT_NEAR(bed.area_fraction, 0.8, 0.008);
    const BedFingerprint f = bed_fingerprint(c, bed, {});
    const auto& p = f.band_area_fraction;
    ASSERT_GE(p.size(), 8u);
    std::vector<std::pair<double, double>> by_distance;  // (|y - y_intruder|, Phi)
    double mean = 0;
    for (std::size_t k = 0; k < p.size(); ++k) {
      by_distance.emplace_back(std::abs(f.band_y[k] - c.intruder_position[1]), p[k]);
      mean += p[k] / static_cast<double>(p.size());
    }
    std::sort(by_distance.begin(), by_distance.end());
    for (int k = 0; k < 4; ++k) centre[drag] += by_distance[k].second / 4;
    for (double v : p) spread[drag] += (v - mean) * (v - mean) / static_cast<double>(p.size());
    spread[drag] = std::sqrt(spread[drag]);
  }
  std::printf("centre bands: %.3f without drag, %.3f with; band spread %.3f against %.3f\n",
              centre[0], centre[1], spread[0], spread[1]);
  EXPECT_GT(centre[0], centre[1] + 0.05);
  EXPECT_LT(spread[0], spread[1]);
}
