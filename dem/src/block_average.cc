// Block averages of a time series (block_average.h).
#include "grainlift/dem/block_average.h"

#include <cmath>

namespace grainlift::dem {

std::vector<double> block_means(const std::vector<double>& x, std::size_t begin, std::size_t end,
                                int blocks) {
  std::vector<double> m;
  if (blocks < 1 || end <= begin || end > x.size()) return m;
  const std::size_t len = (end - begin) / static_cast<std::size_t>(blocks);
  if (len == 0) return m;
  for (int b = 0; b < blocks; ++b) {
    double s = 0;
    const std::size_t lo = begin + static_cast<std::size_t>(b) * len;
    for (std::size_t k = lo; k < lo + len; ++k) s += x[k];
    m.push_back(s / static_cast<double>(len));
  }
  return m;
}

MeanError mean_and_error(const std::vector<double>& v) {
  MeanError r;
  if (v.empty()) return r;
  const double n = static_cast<double>(v.size());
  for (double a : v) r.mean += a;
  r.mean /= n;
  if (v.size() < 2) return r;
  double ss = 0;
  for (double a : v) ss += (a - r.mean) * (a - r.mean);
  r.se = std::sqrt(ss / (n - 1) / n);
  return r;
}

}  // namespace grainlift::dem
