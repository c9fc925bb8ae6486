// The touching grain-grain and grain-wall pairs of the last step as contacts with a branch
// vector, for the measurements that coarse-grain the contact stress (fields, far field).
#pragma once

#include <cstdint>

#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem::detail {

/// @brief Calls f(fx, fy, lx, ly, mx, my) for every listed pair of @p s whose stored force is
/// not zero (set_store_pair_forces(true)): (fx, fy) the force on the grain, (lx, ly) the branch
/// vector from the partner's centre to the grain's (minimum image), (mx, my) the midpoint of the
/// branch vector in the lab frame (not wrapped). In pair order.
template <class F>
void for_each_pair_contact(const DemSystem& s, F f) {
  const ParticleArrays& p = s.particles();
  const NeighborList& nl = s.neighbors();
  const PeriodicBox& box = s.box();
  for (int i = 0; i < s.grains(); ++i) {
    for (std::int64_t k = nl.first[i]; k < nl.first[i + 1]; ++k) {
      if (nl.fx[k] == 0 && nl.fy[k] == 0) continue;
      const int j = nl.partner[k];
      double lx = p.x[i] - p.x[j], ly = p.y[i] - p.y[j];
      box.min_image(lx, ly);
      f(nl.fx[k], nl.fy[k], lx, ly, p.x[j] + 0.5 * lx, p.y[j] + 0.5 * ly);
    }
  }
}

}  // namespace grainlift::dem::detail
