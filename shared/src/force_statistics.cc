#include "grainlift/shared/force_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace grainlift {

DragLift project_drag_lift(double fx, double fy, double vx, double vy) {
  const double v = std::hypot(vx, vy);
  if (!(v > 0)) throw std::invalid_argument("project_drag_lift: zero velocity");
  const double ex = vx / v, ey = vy / v;
  // z x e = (-ey, ex)
  return {-(fx * ex + fy * ey), fx * (-ey) + fy * ex};
}

BlockMean block_mean(const std::vector<double>& series, std::size_t blocks) {
  BlockMean r;
  const std::size_t n = series.size();
  if (n == 0) {
    r.mean = r.stderr_ = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  const std::size_t B = std::max<std::size_t>(1, std::min(blocks, n));
  const std::size_t len = n / B, start = n - len * B;
  std::vector<double> means(B, 0.0);
  for (std::size_t b = 0; b < B; ++b) {
    for (std::size_t i = 0; i < len; ++i) means[b] += series[start + b * len + i];
    means[b] /= double(len);
  }
  double mean = 0;
  for (double m : means) mean += m;
  mean /= double(B);
  double var = 0;
  for (double m : means) var += (m - mean) * (m - mean);
  r.mean = mean;
  r.blocks = B;
  r.samples = len * B;
  r.stderr_ = B >= 2 ? std::sqrt(var / double(B - 1) / double(B))
                     : std::numeric_limits<double>::quiet_NaN();
  if (B >= 3 && var > 0) {
    double c1 = 0;
    for (std::size_t b = 0; b + 1 < B; ++b) c1 += (means[b] - mean) * (means[b + 1] - mean);
    r.lag1 = c1 / var;
  }
  const double rho = std::min(0.9, std::max(0.0, r.lag1));
  r.stderr_corrected = r.stderr_ * std::sqrt((1 + rho) / (1 - rho));
  return r;
}

}  // namespace grainlift
