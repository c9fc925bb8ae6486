// Smoothing of a pointwise surface trace with the DEM's kernel (surface_smoothing.h).
#include "grainlift/shared/surface/surface_smoothing.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "grainlift/shared/surface/surface_stress.h"

namespace grainlift {

namespace {
constexpr double pi = 3.14159265358979323846;

/// dtheta_j: half the periodic distance between the neighbours of each angle (the arc each
/// sample stands for; 2 pi / N on an even grid).
std::vector<double> arc_weights(const std::vector<double>& theta) {
  const std::size_t n = theta.size();
  std::vector<double> t(n), w(n);
  for (std::size_t j = 0; j < n; ++j) t[j] = wrap_angle(theta[j]) + pi;  // in (0, 2 pi]
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return t[a] < t[b]; });
  for (std::size_t k = 0; k < n; ++k) {
    const double prev = k == 0 ? t[order[n - 1]] - 2 * pi : t[order[k - 1]];
    const double next = k + 1 == n ? t[order[0]] + 2 * pi : t[order[k + 1]];
    w[order[k]] = 0.5 * (next - prev);
  }
  return w;
}
}  // namespace

std::vector<double> smooth_onto_grid(const std::vector<double>& theta,
                                     const std::vector<double>& values, int M, double width_deg) {
  if (theta.size() != values.size() || theta.empty())
    throw std::invalid_argument("smooth_onto_grid: need as many values as angles, at least one");
  // The trace as the point forces f_j = sigma(theta_j) R dtheta_j, averaged by the DEM's own
  // estimator (Guillard eq. (A4)), one frame; D = 2 m makes R = 1 m.
  const double D = 2.0, R = 1.0;
  SurfaceStressEstimator kernel(M, width_deg, D);
  const std::vector<double> arc = arc_weights(theta);
  for (std::size_t j = 0; j < theta.size(); ++j) kernel.add(theta[j], values[j] * R * arc[j], 0.0);
  kernel.end_frame();
  return kernel.result().sigma_n;
}

std::vector<double> smooth_on_grid(const std::vector<double>& values, double width_deg) {
  if (width_deg == 0) return values;
  const int M = static_cast<int>(values.size());
  return smooth_onto_grid(surface_angle_grid(M), values, M, width_deg);
}

}  // namespace grainlift
