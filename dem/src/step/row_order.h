// The memory order the neighbour list and the threads' slabs of rows want: disks in rows of
// cells, bottom row first, x order within a row. Used where a bed is packed (packing.cc) and
// where a run renumbers its grains (grain_order.cc).
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace grainlift::dem::detail {

/// @brief The order of the @p n disks at (@p x, @p y) in rows of cells @p d wide: rows counted
/// from @p ymin, columns from @p xmin over @p width (the last column takes the rest, a disk
/// outside the width the nearest column); stable, so disks of one cell keep their index order.
/// Returns order, order[k] the index of the k-th disk.
inline std::vector<int> rows_of_cells_order(const double* x, const double* y, int n, double xmin,
                                            double width, double ymin, double d) {
  const long ncx = std::max(1L, static_cast<long>(width / d));
  std::vector<long> key(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const long cx = std::min(ncx - 1, std::max(0L, static_cast<long>((x[i] - xmin) / d)));
    const long cy = static_cast<long>(std::floor((y[i] - ymin) / d));
    key[static_cast<std::size_t>(i)] = cy * ncx + cx;
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return key[static_cast<std::size_t>(a)] < key[static_cast<std::size_t>(b)];
  });
  return order;
}

}  // namespace grainlift::dem::detail
