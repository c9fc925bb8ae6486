// The continuum's pointwise surface trace smoothed with the DEM's kernel (Guillard 2014
// eq. (A4), surface_smoothing.h): the smoothed trace is the periodic convolution with a
// Gaussian of unit integral, which multiplies the k-th Fourier mode by exp(-k^2 s^2 / 2), and
// it is the same number the DEM estimator makes of point contacts that sample the trace.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "grainlift/shared/surface/surface_smoothing.h"
#include "grainlift/shared/surface/surface_stress.h"

using namespace grainlift;

namespace {
constexpr double pi = 3.14159265358979323846;
constexpr double deg = pi / 180;

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (std::size_t m = 0; m < a.size(); ++m) d = std::max(d, std::abs(a[m] - b[m]));
  return d;
}

/// Fourier series of |sin theta| = 2/pi - (4/pi) sum_k cos(2 k theta) / (4 k^2 - 1), each mode
/// multiplied by the kernel's exp(-(2k)^2 s^2 / 2): the exact convolution (modes beyond
/// k = 200 are below exp(-200^2 s^2 2) for s >= 1 deg, nothing in double precision).
double smoothed_abs_sin(double theta, double width_deg) {
  double v = 2 / pi;
  for (int k = 1; k <= 200; ++k)
    v -=
        4 / pi * kernel_attenuation(2 * k, width_deg) * std::cos(2 * k * theta) / (4.0 * k * k - 1);
  return v;
}
}  // namespace

TEST(SurfaceSmoothing, LowModesAreAttenuatedByTheKernelTransferFunction) {
  // f = a0 + a1 cos(theta) + b2 sin(2 theta) on the shared grid, M = 64, s = 8 deg. The
  // convolution gives a0 + a1 e^{-s^2/2} cos(theta) + b2 e^{-2 s^2} sin(2 theta). The midpoint
  // rule on N = 64 angles multiplies mode k by sum_n exp(-(k + n N)^2 s^2 / 2) instead
  // (surface_smoothing.h): the extra terms are < 2 exp(-(N - 2)^2 s^2 / 2) = 1e-16 of each
  // amplitude, and the wrap to (-pi, pi] drops tails of erfc(pi / (s sqrt 2)) ~ 1e-110; so the
  // tolerance is rounding, 1e-12 of the largest amplitude. The same from the 8-times finer grid.
  const double a0 = 300, a1 = -120, b2 = 45, s = 8.0;
  const int M = 64;
  const auto f = [&](double t) { return a0 + a1 * std::cos(t) + b2 * std::sin(2 * t); };
  const double alias = 2 * std::exp(-0.5 * std::pow((M - 2) * s * deg, 2));
  ASSERT_LT(alias, 1e-15);
  const auto theta = surface_angle_grid(M);
  const auto fine_theta = surface_angle_grid(8 * M);
  std::vector<double> values, fine_values, expected;
  for (double t : theta) {
    values.push_back(f(t));
    expected.push_back(a0 + a1 * kernel_attenuation(1, s) * std::cos(t) +
                       b2 * kernel_attenuation(2, s) * std::sin(2 * t));
  }
  for (double t : fine_theta) fine_values.push_back(f(t));
  EXPECT_LT(max_abs_difference(smooth_on_grid(values, s), expected), 1e-12 * a0);
  EXPECT_LT(max_abs_difference(smooth_onto_grid(fine_theta, fine_values, M, s), expected),
            1e-12 * a0);
}

TEST(SurfaceSmoothing, ACoarseGridAliasesTheKernelAsPoissonSummationPredicts) {
  // Why the continuum glue smooths from a finer grid: on M = 16 angles (22.5 deg) an 8 deg
  // kernel is under-resolved and the midpoint rule multiplies mode k by
  // A_k = sum_n exp(-(k + 16 n)^2 s^2 / 2), n over all integers; A_0 = 1.166, not 1. Both
  // the constant and cos(3 theta) must come out multiplied by A_k to 1e-12.
  const int M = 16;
  const double s = 8.0;
  const auto factor = [&](int k) {
    double A = 0;
    for (int n = -5; n <= 5; ++n) A += std::exp(-0.5 * std::pow((k + M * n) * s * deg, 2));
    return A;
  };
  const auto theta = surface_angle_grid(M);
  std::vector<double> one(M, 1.0), c3;
  for (double t : theta) c3.push_back(std::cos(3 * t));
  const auto s1 = smooth_on_grid(one, s), s3 = smooth_on_grid(c3, s);
  EXPECT_GT(factor(0), 1.1);
  for (int m = 0; m < M; ++m) {
    EXPECT_NEAR(s1[m], factor(0), 1e-12);
    EXPECT_NEAR(s3[m], factor(3) * c3[m], 1e-12);
  }
}

TEST(SurfaceSmoothing, AConstantStaysConstant) {
  // The kernel integrates to 1 (eq. A4 normalised as the DEM estimator does), so a constant
  // comes back to 1e-12 relative wherever the grid resolves the kernel: aliasing
  // 2 exp(-(N s)^2 / 2) and the dropped tails erfc(pi / (s sqrt 2)) are both < 1e-15 for
  // N = 64 at s = 8, 15 deg and N = 512 at s = 2 ... 15 deg.
  const double p = 523.25;
  const std::vector<double> on_grid(64, p);
  for (double s : {8.0, 15.0})
    for (double v : smooth_on_grid(on_grid, s)) EXPECT_NEAR(v, p, 1e-12 * p) << s;
  const auto fine_theta = surface_angle_grid(512);
  const std::vector<double> fine(512, p);
  for (double s : {2.0, 4.0, 8.0, 15.0})
    for (double v : smooth_onto_grid(fine_theta, fine, 64, s)) EXPECT_NEAR(v, p, 1e-12 * p) << s;
  // width 0: the pointwise trace itself
  EXPECT_EQ(smooth_on_grid(on_grid, 0.0), on_grid);
}

TEST(SurfaceSmoothing, IsWhatTheDemEstimatorMakesOfContactsSamplingTheTrace) {
  // Like with like: N point contacts at theta_j = (j + 1/2) 2 pi / N, each carrying the force
  // of its arc, f_j = sigma(theta_j) R (2 pi / N) (N/m), fed to SurfaceStressEstimator over
  // three identical frames, give sum_j g_s(theta_m - theta_j) sigma(theta_j) 2 pi / N: the
  // operation smooth_onto_grid performs (it runs the estimator on those forces), so the two
  // agree to rounding, 1e-12 of the trace's scale. The trace has kinks (|sin theta|, like the
  // continuum's C0 trace) and a tangential part; D = 0.1 m, s = 8 deg, N = 512, M = 64.
  const int M = 64, N = 512, frames = 3;
  const double D = 0.1, R = D / 2, s = 8.0, P = 400;
  const auto fine_theta = surface_angle_grid(N);
  std::vector<double> sn, st;
  for (double t : fine_theta) {
    sn.push_back(P * (1 + std::abs(std::sin(t)) + 0.3 * std::cos(t)));
    st.push_back(0.2 * P * std::abs(std::cos(t)) * std::sin(t));
  }
  SurfaceStressEstimator dem(M, s, D);
  for (int f = 0; f < frames; ++f) {
    for (int j = 0; j < N; ++j)
      dem.add(fine_theta[j], sn[j] * R * 2 * pi / N, st[j] * R * 2 * pi / N);
    dem.end_frame();
  }
  const SurfaceDistribution r = dem.result();
  EXPECT_LT(max_abs_difference(r.sigma_n, smooth_onto_grid(fine_theta, sn, M, s)), 1e-12 * P);
  EXPECT_LT(max_abs_difference(r.sigma_t, smooth_onto_grid(fine_theta, st, M, s)), 1e-12 * P);
}

TEST(SurfaceSmoothing, OversamplingAKinkedTraceConvergesToTheConvolution) {
  // |sin theta| has kinks (as the continuum's trace at face vertices); its modes fall like
  // 2 / (pi q^2) and those at multiples of the sampling number N fold back onto low modes,
  // where the kernel passes them with weight ~ 1. Summing that over the kernel's pass band,
  // sum_p exp(-p^2 s^2 / 2) = sqrt(2 pi) / s, and the even folds n N only (|sin| has even modes
  // alone, and N is even), the error is below
  //   bound(N) = 2 sum_{n >= 1} 2 / (pi (n N)^2) * sqrt(2 pi) / s = (2 pi / 3) sqrt(2 pi) / (s
  //   N^2),
  // 9.2e-3 for N = 64 and 1.4e-4 for N = 512 (s = 8 deg). Measured against the exact
  // convolution, the error must stay below the bound, and smoothing from 8 M samples must be
  // more than 16 times better than from M (the 1/N^2 law gives 64).
  const int M = 64;
  const double s = 8.0;
  const auto bound = [&](int N) { return 2 * pi / 3 * std::sqrt(2 * pi) / (s * deg * N * N); };
  const auto theta = surface_angle_grid(M);
  std::vector<double> exact;
  for (double t : theta) exact.push_back(smoothed_abs_sin(t, s));
  double err[2];
  int k = 0;
  for (int N : {M, 8 * M}) {
    const auto fine_theta = surface_angle_grid(N);
    std::vector<double> f;
    for (double t : fine_theta) f.push_back(std::abs(std::sin(t)));
    err[k] = max_abs_difference(smooth_onto_grid(fine_theta, f, M, s), exact);
    EXPECT_LT(err[k], bound(N)) << N;
    ++k;
  }
  RecordProperty("error_from_M", std::to_string(err[0]));
  RecordProperty("error_from_8M", std::to_string(err[1]));
  EXPECT_GT(err[0], 16 * err[1]);
}
