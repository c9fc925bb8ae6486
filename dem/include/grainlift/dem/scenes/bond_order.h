// The local bond-orientational (hexatic) order of a 2D packing of disks (Nelson & Halperin, PRB
// 19, 2457, 1979; for sheared disks e.g. Tsai & Gollub, PRE 70, 031303, 2004): for disk i with
// neighbours j at angles theta_ij, psi6_i = (1 / n_i) sum_j exp(6 i theta_ij). |psi6_i| is 1 in
// a triangular crystal and lower where the packing is disordered (the sheared layers of the
// creeping-layer cells: 0.5-0.7; their resting beds: 0.8-0.98). Used to tell a layer that has
// ordered (a solid plug) from one that flows.
#pragma once

#include <vector>

namespace grainlift::dem {

/// Centre distance, in units of r_i + r_j, below which two disks are neighbours: between the
/// first shell of a triangular packing (1) and its second (sqrt 3), near the first minimum of
/// a dense disk packing's pair correlation.
inline constexpr double kBondNeighbourRange = 1.4;

/// |psi6_i| of every disk (x, y, r of equal length), periodic in x with @p period (<= 0: not
/// periodic); NaN for a disk with fewer than two neighbours.
std::vector<double> hexatic_order(const std::vector<double>& x, const std::vector<double>& y,
                                  const std::vector<double>& r, double period,
                                  double range = kBondNeighbourRange);

}  // namespace grainlift::dem
