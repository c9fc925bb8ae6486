// The local hexatic order |psi6| (bond_order.h) on packings whose answer is known: a triangular
// crystal (neighbours at multiples of 60 degrees: exactly 1), a square lattice (four neighbours
// 90 degrees apart, the diagonals at sqrt 2 d beyond the range: exactly 0), a disk with a
// single neighbour (undefined), and the periodic image across x.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "grainlift/dem/scenes/bond_order.h"

namespace gd = grainlift::dem;

namespace {

struct Disks {
  std::vector<double> x, y, r;
  void add(double xi, double yi, double ri) { x.push_back(xi), y.push_back(yi), r.push_back(ri); }
};

/// @p cols x @p rows disks of diameter @p d on a triangular lattice, periodic in x over cols d.
Disks triangular(int cols, int rows, double d) {
  Disks p;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i)
      p.add((i + 0.5 * (j % 2)) * d, j * d * std::sqrt(3.0) / 2, 0.5 * d);
  return p;
}

}  // namespace

// Every disk of a triangular crystal periodic in x has |psi6| = 1, to round-off (1e-12); the
// top and bottom rows (four neighbours, every angle a multiple of 60 degrees) also have 1.
TEST(BondOrder, TriangularCrystalIsPerfectlyOrdered) {
  const Disks p = triangular(10, 6, 0.002);
  const std::vector<double> order = gd::hexatic_order(p.x, p.y, p.r, 10 * 0.002);
  ASSERT_EQ(order.size(), p.x.size());
  for (const double o : order) EXPECT_NEAR(o, 1.0, 1e-12);
}

// A square lattice (period 8 d in x): psi6 sums exp(6 i theta) over theta = 0, 90, 180, 270
// degrees, 1 - 1 + 1 - 1 = 0, to round-off (1e-12).
TEST(BondOrder, SquareLatticeHasNoHexaticOrder) {
  Disks p;
  const double d = 0.002;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 8; ++i) p.add(i * d, j * d, 0.5 * d);
  const std::vector<double> order = gd::hexatic_order(p.x, p.y, p.r, 8 * d);
  for (std::size_t k = 8; k < 32; ++k) EXPECT_NEAR(order[k], 0.0, 1e-12) << k;
}

// The period counts: a square lattice's left-edge disk (index 8, second row) has three
// neighbours without it (0, 90, 270 degrees: |1 - 1 - 1| / 3 = 1/3) and four with it (0). A
// pair of disks: NaN (one neighbour each); arrays of different lengths are refused.
TEST(BondOrder, PeriodicImagesAndLoneDisks) {
  Disks p;
  const double d = 0.002;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 8; ++i) p.add(i * d, j * d, 0.5 * d);
  EXPECT_NEAR(gd::hexatic_order(p.x, p.y, p.r, 0)[8], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(gd::hexatic_order(p.x, p.y, p.r, 8 * d)[8], 0.0, 1e-12);
  Disks pair;
  pair.add(0, 0, 0.001);
  pair.add(0.002, 0, 0.001);
  for (const double o : gd::hexatic_order(pair.x, pair.y, pair.r, 0)) EXPECT_TRUE(std::isnan(o));
  EXPECT_THROW(gd::hexatic_order({0.0}, {0.0, 1.0}, {0.001}, 0), std::invalid_argument);
}
