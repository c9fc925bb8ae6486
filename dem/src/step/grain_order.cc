// The grains kept in rows of cells (SystemOptions::sort_every): every so many steps the grains
// are renumbered, bottom row of cells first and x order within a row, so that the threads'
// slabs of rows stay compact as the flow mixes the bed (the order the bed was packed in
// decays as the intruder stirs it; docs/performance.md, "Threads").
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "grainlift/dem/system/dem_system.h"
#include "step/row_order.h"

namespace grainlift::dem {

namespace {
/// @p v[0, n) reordered so that new[k] = old[order[k]].
template <class T>
void permute(std::vector<T>& v, const std::vector<int>& order, std::size_t stride = 1) {
  const std::size_t n = order.size();
  if (v.size() < n * stride) return;
  std::vector<T> tmp(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n * stride));
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t c = 0; c < stride; ++c)
      v[k * stride + c] = tmp[static_cast<std::size_t>(order[k]) * stride + c];
  }
}
}  // namespace

void DemSystem::sort_grains_into_rows() {
  const int n = n_grains_;
  if (n < 2) return;
  double rmax = 0;
  for (int i = 0; i < n; ++i) rmax = std::max(rmax, p_.r[i]);
  const PeriodicBox& box = opt_.box;
  const std::vector<int> order = detail::rows_of_cells_order(
      p_.x.data(), p_.y.data(), n, box.xmin, box.xmax - box.xmin, box.ymin, 2.0 * rmax);
  bool same = true;
  for (int k = 0; k < n && same; ++k) same = order[static_cast<std::size_t>(k)] == k;
  if (same) return;
  std::vector<int> new_of_old(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) new_of_old[static_cast<std::size_t>(order[k])] = k;
  // the intruder candidates' slots and flags are set again by the build
  for (int g : ic_.grain) {
    ic_slot_[static_cast<std::size_t>(g)] = -1;
    grain_flags_[static_cast<std::size_t>(g)] &= static_cast<std::uint8_t>(~kCandidate);
  }
  for (auto* v : {&p_.x, &p_.y, &p_.vx, &p_.vy, &p_.w, &p_.ax, &p_.ay, &p_.alpha, &p_.r,
                  &p_.inv_m, &p_.inv_i, &p_.mass, &tq_}) {
    permute(*v, order);
  }
  permute(fxy_, order, 2);
  permute(p_.x_build, order);
  permute(p_.y_build, order);
  permute(touched_, order);
  permute(grain_flags_, order);
  permute(dormant_, order);
  nl_.renumber(new_of_old);
  // the candidates (sorted by grain) with their springs
  const std::size_t nc = ic_.grain.size();
  std::vector<std::size_t> by(nc);
  std::iota(by.begin(), by.end(), 0);
  for (auto& g : ic_.grain) g = new_of_old[static_cast<std::size_t>(g)];
  std::sort(by.begin(), by.end(), [&](std::size_t a, std::size_t b) {
    return ic_.grain[a] < ic_.grain[b];
  });
  IntruderContacts sorted;
  for (std::size_t m : by) {
    sorted.grain.push_back(ic_.grain[m]);
    sorted.sx.push_back(ic_.sx[m]);
    sorted.sy.push_back(ic_.sy[m]);
  }
  ic_.grain.swap(sorted.grain);
  ic_.sx.swap(sorted.sx);
  ic_.sy.swap(sorted.sy);
}

}  // namespace grainlift::dem
