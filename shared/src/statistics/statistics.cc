// Block means, pooled beds and Richardson extrapolation (statistics.h). The sums run in the
// order of python/grainlift/stats.py's loops, so both give the same numbers.
#include "grainlift/shared/statistics/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace grainlift {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Largest lag-1 autocorrelation the correction uses: at most sqrt(1.9 / 0.1) = 4.4 times the
/// plain error, so that a short series' noisy estimate of r cannot blow the error up.
constexpr double kMaxLag1 = 0.9;
}  // namespace

std::vector<double> block_means(const std::vector<double>& series, std::size_t blocks) {
  const std::size_t n = series.size();
  if (n == 0) return {};
  const std::size_t B = std::max<std::size_t>(1, std::min(blocks, n));
  const std::size_t len = n / B, start = n - len * B;
  std::vector<double> means(B, 0.0);
  for (std::size_t b = 0; b < B; ++b) {
    double s = 0;
    for (std::size_t i = 0; i < len; ++i) s += series[start + b * len + i];
    means[b] = s / double(len);
  }
  return means;
}

BlockMean block_mean_of(const std::vector<double>& means, std::size_t samples) {
  BlockMean r;
  const std::size_t B = means.size();
  r.blocks = B;
  r.samples = samples;
  if (B == 0) {
    r.mean = r.stderr_ = r.stderr_corrected = kNaN;
    return r;
  }
  double mean = 0;
  for (double m : means) mean += m;
  mean /= double(B);
  double var = 0;
  for (double m : means) var += (m - mean) * (m - mean);
  r.mean = mean;
  r.stderr_ = B >= 2 ? std::sqrt(var / double(B - 1) / double(B)) : kNaN;
  if (B >= 3 && var > 0) {
    double c1 = 0;
    for (std::size_t b = 0; b + 1 < B; ++b) c1 += (means[b] - mean) * (means[b + 1] - mean);
    r.lag1 = c1 / var;
  }
  // AR(1): Var(mean of B) = Var(m_b) / B (1 + r) / (1 - r) for B much larger than 1 / (1 - r)
  const double rho = std::min(kMaxLag1, std::max(0.0, r.lag1));
  r.stderr_corrected = r.stderr_ * std::sqrt((1 + rho) / (1 - rho));
  return r;
}

BlockMean block_mean(const std::vector<double>& series, std::size_t blocks) {
  const std::vector<double> means = block_means(series, blocks);
  const std::size_t len = means.empty() ? 0 : series.size() / means.size();
  return block_mean_of(means, len * means.size());
}

PooledMean pooled_mean(const std::vector<double>& means, const std::vector<double>& errors) {
  const std::size_t n = means.size();
  if (!errors.empty() && errors.size() != n) {
    throw std::invalid_argument("pooled_mean: " + std::to_string(n) + " means but " +
                                std::to_string(errors.size()) + " errors");
  }
  PooledMean p;
  p.beds = n;
  p.between = p.within = kNaN;
  if (n == 0) {
    p.mean = p.error = kNaN;
    return p;
  }
  double mean = 0;
  for (double m : means) mean += m;
  mean /= double(n);
  p.mean = mean;
  if (n >= 2) {
    double ss = 0;
    for (double m : means) ss += (m - mean) * (m - mean);
    p.between = std::sqrt(ss / double(n - 1) / double(n));
  }
  if (!errors.empty()) {
    double s2 = 0;
    for (double e : errors) s2 += e * e;
    p.within = std::sqrt(s2) / double(n);
  }
  const bool b = std::isfinite(p.between), w = std::isfinite(p.within);
  p.error = b && w ? std::max(p.between, p.within) : b ? p.between : w ? p.within : kNaN;
  return p;
}

Richardson richardson(const std::vector<double>& h, const std::vector<double>& values,
                      double min_order, double max_order) {
  if (h.size() != 3 || values.size() != 3) {
    throw std::invalid_argument("richardson: needs three cell sizes and three values");
  }
  if (!(h[0] > h[1] && h[1] > h[2] && h[2] > 0)) {
    throw std::invalid_argument("richardson: cell sizes must be positive and decreasing");
  }
  const double r = h[0] / h[1];
  if (std::abs(h[1] / h[2] - r) > 1e-9 * r) {
    throw std::invalid_argument("richardson: cell sizes without a constant refinement ratio");
  }
  const double e1 = values[1] - values[0], e2 = values[2] - values[1];
  Richardson out;
  out.limit = values[2];
  out.error = std::abs(e2);
  if (e1 == 0 || e2 == 0 || (e1 > 0) != (e2 > 0)) {
    out.order = kNaN;
    return out;
  }
  out.order = std::log(e1 / e2) / std::log(r);
  if (!(min_order <= out.order && out.order <= max_order)) return out;
  out.limit = values[2] + e2 / (std::pow(r, out.order) - 1);
  out.error = std::abs(out.limit - values[2]);
  out.accepted = true;
  return out;
}

}  // namespace grainlift
