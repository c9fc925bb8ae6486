// The Gaussian-kernel surface-stress estimator (Guillard 2014 eq. A4) recovers a known
// distribution sampled by point forces; the symmetry split and surface integration are exact
// for known distributions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "grainlift/shared/surface/surface_stress.h"

using namespace grainlift;

namespace {
constexpr double pi = 3.14159265358979323846;
}

TEST(SurfaceStress, RecoversCosineAndSineAmplitudesWithinOnePercent) {
  // sigma_n = P0 (1 + a cos theta + b sin theta) sampled by N point forces f_i = sigma_n(theta_i)
  // * (pi D / N) (per unit length) at random angles, over many frames. The kernel smooths mode
  // k by exp(-k^2 s^2 / 2); undoing that, a and b must come back within 1 %.
  const double P0 = 250, a = 0.6, b = -0.3, D = 0.1;
  const int M = 64, N = 400, frames = 200;
  SurfaceStressEstimator est(M, 8.0, D);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-pi, pi);
  for (int f = 0; f < frames; ++f) {
    for (int i = 0; i < N; ++i) {
      const double t = u(rng);
      const double s = P0 * (1 + a * std::cos(t) + b * std::sin(t));
      est.add(t, s * pi * D / N, 0.1 * s * pi * D / N);
    }
    est.end_frame();
  }
  const SurfaceDistribution r = est.result();
  const double P0_hat = fourier_mode(r.sigma_n, 0).first;
  const auto [a1, b1] = fourier_mode(r.sigma_n, 1);
  const double att = kernel_attenuation(1, 8.0);
  EXPECT_NEAR(P0_hat, P0, 0.01 * P0);
  EXPECT_NEAR(a1 / att / P0_hat, a, 0.01 * std::abs(a));
  EXPECT_NEAR(b1 / att / P0_hat, b, 0.01 * std::abs(b));
  // The tangential part scales the same way (sigma_t = 0.1 sigma_n here), 1 %.
  EXPECT_NEAR(fourier_mode(r.sigma_t, 0).first, 0.1 * P0, 0.001 * P0);
}

TEST(SurfaceStress, KernelSmoothingMatchesItsTransferFunction) {
  // On a dense uniform sampling of cos(3 theta) the measured amplitude is exp(-9 s^2 / 2)
  // of the true one (s = 15 deg), within 1e-3.
  const int M = 90, N = 3600;
  const double D = 1.0;
  SurfaceStressEstimator est(M, 15.0, D);
  for (int i = 0; i < N; ++i) {
    const double t = (i + 0.5) * 2 * pi / N;
    est.add(t, std::cos(3 * t) * pi * D / N, 0);
  }
  est.end_frame();
  const auto [a3, b3] = fourier_mode(est.result().sigma_n, 3);
  EXPECT_NEAR(a3, kernel_attenuation(3, 15.0), 1e-3);
  EXPECT_NEAR(b3, 0.0, 1e-3);
}

TEST(SurfaceStress, SymmetrySplitSeparatesCosineAndSine) {
  // s = 2 + cos(theta) + 0.5 sin(theta): symmetric part 2 + cos, antisymmetric part 0.5 sin.
  const auto theta = surface_angle_grid(64);
  std::vector<double> s, sym, anti;
  for (double t : theta) s.push_back(2 + std::cos(t) + 0.5 * std::sin(t));
  symmetry_split(s, sym, anti);
  for (std::size_t m = 0; m < theta.size(); ++m) {
    EXPECT_NEAR(sym[m], 2 + std::cos(theta[m]), 1e-12);
    EXPECT_NEAR(anti[m], 0.5 * std::sin(theta[m]), 1e-12);
  }
}

TEST(SurfaceStress, IntegratedForceOfAKnownDistribution) {
  // sigma_n = P0 (1 + a cos theta + b sin theta), sigma_t = tau: the force on the intruder
  // along V is -pi R P0 a (drag pi R P0 a), across V -pi R P0 b, torque 2 pi R^2 tau.
  // The midpoint rule is exact for these low modes to 1e-12.
  const double P0 = 100, a = 0.5, b = 0.2, tau = 3, D = 0.2, R = 0.1;
  SurfaceDistribution s;
  s.theta = surface_angle_grid(64);
  for (double t : s.theta) {
    s.sigma_n.push_back(P0 * (1 + a * std::cos(t) + b * std::sin(t)));
    s.sigma_t.push_back(tau);
  }
  const auto f = integrate_surface(s, D);
  EXPECT_NEAR(f[0], -pi * R * P0 * a, 1e-9);
  EXPECT_NEAR(f[1], -pi * R * P0 * b, 1e-9);
  EXPECT_NEAR(f[2], 2 * pi * R * R * tau, 1e-12);
}

TEST(SurfaceStress, HistogramBinsAtPiOverTwelve) {
  // 24 bins from -pi: a contact at theta = 0.01 falls in bin 12, at -0.01 in bin 11; slip
  // fraction and per-frame means are exact; the slip velocity is a mean per contact that
  // leaves out the contacts without one (NaN).
  ContactHistogram h(24);
  h.add(0.01, 2.0, 1.0, true, 0.5);
  h.add(0.02, 4.0, -1.0, false, -0.25);
  h.add(-0.01, 1.0, 0.0, false, std::numeric_limits<double>::quiet_NaN());
  h.end_frame();
  h.end_frame();
  const auto r = h.result();
  EXPECT_NEAR(r.theta_hi[0] - r.theta_lo[0], pi / 12, 1e-14);
  EXPECT_DOUBLE_EQ(r.contact_count[12], 1.0);   // 2 contacts / 2 frames
  EXPECT_DOUBLE_EQ(r.normal_force[12], 3.0);    // 6 N/m / 2 frames
  EXPECT_DOUBLE_EQ(r.slip_fraction[12], 0.5);
  EXPECT_DOUBLE_EQ(r.contact_count[11], 0.5);
  EXPECT_DOUBLE_EQ(r.slip_fraction[0], 0.0);
  ASSERT_TRUE(r.slip_velocity.has_value());
  EXPECT_DOUBLE_EQ((*r.slip_velocity)[12], 0.125);  // (0.5 - 0.25) / 2 contacts
  EXPECT_DOUBLE_EQ((*r.slip_velocity)[11], 0.0);    // its one contact had none
}

TEST(SurfaceStress, HistogramWithoutSlipVelocities) {
  // Contacts without a slip velocity (a LAMMPS import): no /histogram/slip_velocity.
  ContactHistogram h(4);
  h.add(0.3, 1.0, 0.0, false, std::numeric_limits<double>::quiet_NaN());
  h.end_frame();
  EXPECT_FALSE(h.result().slip_velocity.has_value());
}

TEST(SurfaceStress, WrapAngle) {
  EXPECT_NEAR(wrap_angle(3 * pi / 2), -pi / 2, 1e-14);
  EXPECT_NEAR(wrap_angle(-pi), pi, 1e-14);
  EXPECT_NEAR(wrap_angle(0.3), 0.3, 1e-15);
}
