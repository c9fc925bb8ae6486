// Verlet-list rebuild of the DEM step: the neighbour list (neighbor_list.cc), the intruder's
// contact candidates with their history carried over, the per-pair constants and the
// scratch of the force loop sized so that the step does not allocate.
#include <algorithm>
#include <cmath>

#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem {

void DemSystem::build_lists(bool sort) {
  if (sort) sort_grains_into_rows();
  nl_.build(opt_.box, p_.x.data(), p_.y.data(), p_.r.data(), n_grains_, n_total_, skin_,
            team_);
  update_sleep();  // sleeping grains: their pairs leave the list (sleeping.cc)
  // Build positions in float, and a bound on |float(x) - x| for the displacement check (which
  // stays conservative): half an ulp of a float relative to the largest coordinate (grains
  // need not stay in the box along a direction without walls), for both axes.
  double cmax = 0;
  for (int i = 0; i < n_total_; ++i) {
    p_.x_build[i] = static_cast<float>(p_.x[i]);
    p_.y_build[i] = static_cast<float>(p_.y[i]);
    cmax = std::max(cmax, std::max(std::fabs(p_.x[i]), std::fabs(p_.y[i])));
  }
  build_round_ = 2.0 * 0x1.0p-24 * cmax;
  // Intruder candidates: grains within R + r + skin, in index order, history carried over.
  for (int g : ic_.grain) {
    ic_slot_[g] = -1;
    grain_flags_[g] &= static_cast<std::uint8_t>(~kCandidate);
  }
  std::swap(ic_, ic_old_);
  ic_.grain.clear();
  if (intruder_.present) {
    intruder_.x_build = intruder_.x;
    intruder_.y_build = intruder_.y;
    for (int g = 0; g < n_grains_; ++g) {
      double dx = p_.x[g] - intruder_.x, dy = p_.y[g] - intruder_.y;
      opt_.box.min_image(dx, dy);
      const double cut = intruder_.r + p_.r[g] + skin_;
      if (dx * dx + dy * dy < cut * cut) ic_.grain.push_back(g);
    }
  }
  const std::size_t nc = ic_.grain.size();
  ic_.sx.assign(nc, 0.0);
  ic_.sy.assign(nc, 0.0);
  for (auto* v : {&ic_.fx, &ic_.fy, &ic_.fn, &ic_.ft, &ic_.nx, &ic_.ny, &ic_.vt})
    v->assign(nc, 0.0);
  ic_.touching.assign(nc, 0);
  ic_.slipping.assign(nc, 0);
  std::size_t a = 0;
  for (std::size_t b = 0; b < nc; ++b) {
    ic_slot_[ic_.grain[b]] = static_cast<int>(b);
    grain_flags_[ic_.grain[b]] |= kCandidate;
    while (a < ic_old_.grain.size() && ic_old_.grain[a] < ic_.grain[b]) ++a;
    if (a < ic_old_.grain.size() && ic_old_.grain[a] == ic_.grain[b]) {
      ic_.sx[b] = ic_old_.sx[a];
      ic_.sy[b] = ic_old_.sy[a];
    }
  }
  // touching-pair scratch of the force loop, one list per chunk of rows: sized here so that
  // the step does not allocate
  const int nc_rows = chunks();
  touch_.resize(static_cast<std::size_t>(nc_rows));
  touch_prev_.resize(static_cast<std::size_t>(nc_rows));
  for (int c = 0; c < nc_rows; ++c) {
    const int lo = c * kChunkRows, hi = std::min(n_grains_, lo + kChunkRows);
    const auto np = static_cast<std::size_t>(nl_.first[hi] - nl_.first[lo]);
    // room for every pair of the chunk (the screening loop writes before it counts)
    touch_[c].size_for(np);
    touch_prev_[c].size_for(np);
  }
  full_history_check_ = true;  // pair indices changed; histories were carried over
  {
    const std::size_t np = nl_.pairs();
    pair_reff_.resize(np);
    pair_meff_.resize(np);
    pair_rs2_.resize(np);
    const double* r = p_.r.data();
    const double* inv_m = p_.inv_m.data();
    for (std::size_t k = 0; k < np; ++k) {
      const int i = nl_.owner[k], j = nl_.partner[k];
      const double ri = r[i], rj = r[j];
      const double rs = ri + rj;
      pair_rs2_[k] = rs * rs;  // as the scalar screen: (r_i + r_j)^2
      pair_reff_[k] = ri * rj / rs;
      pair_meff_[k] = 1.0 / (inv_m[i] + inv_m[j]);
    }
    radii_scaled_ = false;
  }
  growth_since_build_ = 0;
  ++builds_;
}


}  // namespace grainlift::dem
