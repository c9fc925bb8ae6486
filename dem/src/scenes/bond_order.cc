// hexatic_order (bond_order.h): neighbours found through horizontal strips as high as the
// largest neighbour distance, so each disk looks at its own strip and the two beside it.
#include "grainlift/dem/scenes/bond_order.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace grainlift::dem {

std::vector<double> hexatic_order(const std::vector<double>& x, const std::vector<double>& y,
                                  const std::vector<double>& r, double period, double range) {
  const std::size_t n = x.size();
  if (y.size() != n || r.size() != n)
    throw std::invalid_argument("hexatic_order: x, y and r differ in length");
  std::vector<double> order(n, std::numeric_limits<double>::quiet_NaN());
  if (n == 0) return order;
  const double r_max = *std::max_element(r.begin(), r.end());
  const double reach = 2 * range * r_max;
  if (!(reach > 0)) return order;
  const double y0 = *std::min_element(y.begin(), y.end());
  std::vector<std::vector<std::size_t>> strips;
  std::vector<long> strip_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    strip_of[i] = static_cast<long>(std::floor((y[i] - y0) / reach));
    const auto s = static_cast<std::size_t>(strip_of[i]);
    if (s >= strips.size()) strips.resize(s + 1);
    strips[s].push_back(i);
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::complex<double> sum = 0;
    int neighbours = 0;
    for (long s = strip_of[i] - 1; s <= strip_of[i] + 1; ++s) {
      if (s < 0 || s >= static_cast<long>(strips.size())) continue;
      for (const std::size_t j : strips[static_cast<std::size_t>(s)]) {
        if (j == i) continue;
        double dx = x[j] - x[i];
        if (period > 0) dx -= period * std::round(dx / period);
        const double dy = y[j] - y[i], cut = range * (r[i] + r[j]);
        if (dx * dx + dy * dy >= cut * cut) continue;
        sum += std::polar(1.0, 6 * std::atan2(dy, dx));
        ++neighbours;
      }
    }
    if (neighbours >= 2) order[i] = std::abs(sum) / neighbours;
  }
  return order;
}

}  // namespace grainlift::dem
