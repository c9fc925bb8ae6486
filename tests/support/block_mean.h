// Mean of a per-sample quantity of a DEM run after its steady-state start, with the standard
// error from contiguous blocks (the samples are correlated; block means of several diameters of
// travel each are close to independent). Shared by the DEM regression and asymptotic tests.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "grainlift/dem/dem_output.h"

namespace grainlift::test_support {

struct MeanAndError {
  double mean = 0, stderr_ = 0;
};

template <class F>
MeanAndError block_mean(const dem::DemOutput& out, F value, int blocks = 10) {
  const std::size_t first = out.steady_start_index;
  const std::size_t per = (out.samples.size() - first) / std::size_t(blocks);
  std::vector<double> means(std::size_t(blocks), 0.0);
  double total = 0;
  for (int b = 0; b < blocks; ++b) {
    double s = 0;
    for (std::size_t k = 0; k < per; ++k) s += value(out.samples[first + std::size_t(b) * per + k]);
    means[std::size_t(b)] = s / double(per);
    total += means[std::size_t(b)];
  }
  MeanAndError r;
  r.mean = total / blocks;
  double var = 0;
  for (double m : means) var += (m - r.mean) * (m - r.mean);
  r.stderr_ = std::sqrt(var / (blocks - 1) / blocks);
  return r;
}

/// L / D and its standard error, the two errors propagated as independent.
inline MeanAndError ratio(const MeanAndError& l, const MeanAndError& d) {
  MeanAndError r;
  r.mean = l.mean / d.mean;
  r.stderr_ = std::abs(r.mean) * std::hypot(l.stderr_ / l.mean, d.stderr_ / d.mean);
  return r;
}

}  // namespace grainlift::test_support
