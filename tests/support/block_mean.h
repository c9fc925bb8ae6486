// Mean of a per-sample quantity of a DEM run after its steady-state start, with the standard
// error from contiguous blocks (the samples are correlated; block means of several diameters of
// travel each are close to independent). Shared by the DEM regression and asymptotic tests; a
// thin adapter: the rule is statistics.h's block_mean.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "grainlift/dem/dem_output.h"
#include "grainlift/shared/statistics/statistics.h"

namespace grainlift::test_support {

struct MeanAndError {
  double mean = 0, stderr_ = 0;
};

/// The block mean of value(sample) over the samples from the steady-state start, in @p blocks
/// blocks, with its correlation-corrected error.
template <class F>
MeanAndError block_mean(const dem::DemOutput& out, F value, int blocks = 10) {
  std::vector<double> series;
  for (std::size_t k = out.steady_start_index; k < out.samples.size(); ++k) {
    series.push_back(value(out.samples[k]));
  }
  const BlockMean m = grainlift::block_mean(series, std::size_t(blocks));
  return {m.mean, m.stderr_corrected};
}

/// L / D and its standard error, the two errors propagated as independent.
inline MeanAndError ratio(const MeanAndError& l, const MeanAndError& d) {
  MeanAndError r;
  r.mean = l.mean / d.mean;
  r.stderr_ = std::abs(r.mean) * std::hypot(l.stderr_ / l.mean, d.stderr_ / d.mean);
  return r;
}

}  // namespace grainlift::test_support
