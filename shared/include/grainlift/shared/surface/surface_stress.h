// Surface stress on the intruder from point forces, shared by both solvers' post-processing.
//   Gaussian kernel: Guillard, Forterre & Pouliquen 2014, eq. (A4): at M angles
//     theta_m = (m + 1/2) 2 pi / M, f(theta_m) = sum_i sqrt(2 pi)/(M s) exp(-(theta_i -
//     theta_m)^2 / (2 s^2)) f_i, sigma = f / (D pi / M) per unit length, averaged over frames.
//   Histogram: Kumar, Dhiman & Reddy 2019, Fig. 6: bins of equal width (pi/12 for 24 bins).
// Angles are measured from the direction of V, counter-clockwise (docs/conventions.md).
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "grainlift/shared/results/run_result.h"

namespace grainlift {

/// Wraps an angle to (-pi, pi].
double wrap_angle(double theta);

/// The shared angle grid theta_m = (m + 1/2) 2 pi / M, m = 0..M-1 (rad).
std::vector<double> surface_angle_grid(int M);

/// Gaussian-kernel estimator of sigma_n(theta), sigma_t(theta) (Guillard eq. A4).
class SurfaceStressEstimator {
 public:
  /// @param M angles; @param width_deg Gaussian standard deviation (deg);
  /// @param diameter intruder diameter D (m).
  SurfaceStressEstimator(int M, double width_deg, double diameter);

  /// Adds one point force at @p theta (rad, from V): @p fn (N/m, compressive positive) and
  /// @p ft (N/m, counter-clockwise positive).
  void add(double theta, double fn, double ft);
  /// Marks the end of one frame (time sample); results are averages over frames.
  void end_frame() { ++frames_; }
  long long frames() const { return frames_; }

  /// sigma_n and sigma_t (Pa) averaged over the frames counted so far.
  SurfaceDistribution result() const;

 private:
  int M_;
  double width_, diameter_;
  std::vector<double> theta_, weight_norm_;
  std::vector<double> fn_, ft_;
  long long frames_ = 0;
};

/// Contact histogram in equal angular bins starting at -pi (Kumar Fig. 6).
class ContactHistogram {
 public:
  explicit ContactHistogram(int bins);
  /// One contact: angle from V (rad), forces (N/m), whether it slips, its slip velocity
  /// (m/s, the surface against the grain, ccw positive; NaN when not known: not counted).
  void add(double theta, double fn, double ft, bool slipping, double vt);
  void end_frame() { ++frames_; }
  SurfaceHistogram result() const;

 private:
  int bins_;
  std::vector<double> count_, fn_, ft_, slip_, vt_, vt_count_;
  long long frames_ = 0;
};

/// Cosine (k > 0) and sine coefficients of a distribution on the grid of surface_angle_grid:
/// values ~ c0 + sum_k (a_k cos k theta + b_k sin k theta). Returns {a_k, b_k}; k = 0 gives
/// {c0, 0}.
std::pair<double, double> fourier_mode(const std::vector<double>& values, int k);

/// Factor by which the Gaussian kernel of standard deviation @p width_deg shrinks the k-th
/// Fourier mode: exp(-k^2 s^2 / 2). Divide a measured mode by it to undo the smoothing.
double kernel_attenuation(int k, double width_deg);

/// Split s(theta) on the grid theta_m into its symmetric (s(theta) + s(-theta))/2 and
/// antisymmetric (s(theta) - s(-theta))/2 parts about the axis of motion.
void symmetry_split(const std::vector<double>& values, std::vector<double>& symmetric,
                    std::vector<double>& antisymmetric);

/// Net force (N/m) and torque (N) of a surface distribution, by the midpoint rule on the grid,
/// in the frame where V points along theta = 0: {F_parallel, F_perpendicular, torque}.
/// F_parallel = -drag, F_perpendicular = lift.
std::array<double, 3> integrate_surface(const SurfaceDistribution& s, double diameter);

}  // namespace grainlift
