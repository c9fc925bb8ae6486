#include "grainlift/shared/rheology/rheology_fit.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlift {

double jop_mu(double I, double mu_s, double mu_2, double I0) {
  // Written as I / (I0 + I) so that I = 0 gives mu_s without dividing by zero.
  return mu_s + (mu_2 - mu_s) * I / (I0 + I);
}

namespace {

/// Refuses points that cannot be weighted: non-finite values, se <= 0, I out of range.
/// @param y, se the measured value and its standard error; @param min_points, min_distinct_I
/// what the fitted law needs; @param I_positive I > 0 required (else I >= 0).
void check_points(const std::vector<ShearPoint>& points, const char* fit, const char* value,
                  double ShearPoint::*y, double ShearPoint::*se, std::size_t min_points,
                  std::size_t min_distinct_I, bool I_positive) {
  if (points.size() < min_points)
    throw std::invalid_argument(fmt::format(
        "{}: {} points given, at least {} needed (the law has {} parameters and chi2/dof needs "
        "one more point)",
        fit, points.size(), min_points, min_points - 1));
  std::vector<double> Is;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const ShearPoint& p = points[k];
    if (!std::isfinite(p.I) || (I_positive ? p.I <= 0 : p.I < 0))
      throw std::invalid_argument(fmt::format("{}: point {} has I = {}; accepted: finite, {} 0",
                                              fit, k, p.I, I_positive ? ">" : ">="));
    if (!std::isfinite(p.*y))
      throw std::invalid_argument(fmt::format("{}: point {} has {} = {}; accepted: finite", fit,
                                              k, value, p.*y));
    if (!std::isfinite(p.*se) || p.*se <= 0)
      throw std::invalid_argument(fmt::format(
          "{}: point {} has {}_stderr = {}; the weights are 1/se^2, so every point needs a "
          "finite se > 0",
          fit, k, value, p.*se));
    Is.push_back(p.I);
  }
  std::sort(Is.begin(), Is.end());
  const auto distinct = static_cast<std::size_t>(std::unique(Is.begin(), Is.end()) - Is.begin());
  if (distinct < min_distinct_I)
    throw std::invalid_argument(fmt::format(
        "{}: the points have {} distinct inertial numbers, at least {} needed: measure over a "
        "range of I",
        fit, distinct, min_distinct_I));
}

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Weighted residuals r_k = (mu_k - mu(I_k)) / se_k and their Jacobian J = -dr/dx with respect
/// to x = (mu_s, mu_2, ln I0), so that the Gauss-Newton step solves (J^T J) dx = J^T r.
struct Linearisation {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  double chi2 = 0;
};

Linearisation linearise(const std::vector<ShearPoint>& points, const Vec3& x) {
  const double mu_s = x[0], mu_2 = x[1], I0 = std::exp(x[2]);
  const auto n = static_cast<Eigen::Index>(points.size());
  Linearisation L{Eigen::VectorXd(n), Eigen::MatrixXd(n, 3), 0};
  for (Eigen::Index k = 0; k < n; ++k) {
    const ShearPoint& p = points[static_cast<std::size_t>(k)];
    const double g = p.I / (I0 + p.I);  // weight of mu_2 in the law
    L.r[k] = (p.mu - (mu_s + (mu_2 - mu_s) * g)) / p.mu_stderr;
    L.J(k, 0) = (1 - g) / p.mu_stderr;
    L.J(k, 1) = g / p.mu_stderr;
    // d g / d ln I0 = -I I0 / (I0 + I)^2
    L.J(k, 2) = -(mu_2 - mu_s) * p.I * I0 / ((I0 + p.I) * (I0 + p.I)) / p.mu_stderr;
  }
  L.chi2 = L.r.squaredNorm();
  return L;
}

double median_I(const std::vector<ShearPoint>& points) {
  std::vector<double> Is;
  for (const auto& p : points) Is.push_back(p.I);
  std::sort(Is.begin(), Is.end());
  const std::size_t m = Is.size() / 2;
  return Is.size() % 2 ? Is[m] : std::sqrt(Is[m - 1] * Is[m]);  // geometric: I is log-spaced
}

}  // namespace

MuIFit fit_mu_i(const std::vector<ShearPoint>& points) {
  check_points(points, "fit_mu_i", "mu", &ShearPoint::mu, &ShearPoint::mu_stderr, 4, 3, true);
  MuIFit fit;
  fit.points = static_cast<int>(points.size());
  const double dof = static_cast<double>(points.size()) - 3;

  // Start values from the data.
  double mu_min = points[0].mu, mu_max = points[0].mu;
  for (const auto& p : points) {
    mu_min = std::min(mu_min, p.mu);
    mu_max = std::max(mu_max, p.mu);
  }
  Vec3 x(mu_min, mu_max + 0.1 * (mu_max - mu_min) + 1e-3, std::log(median_I(points)));

  // Levenberg-Marquardt with Marquardt's scaling: (A + lambda diag(A)) dx = J^T r.
  constexpr int max_iterations = 500;
  constexpr double step_tolerance = 1e-11;   // relative change of every parameter
  constexpr double lambda_give_up = 1e14;    // no step lowers chi2: at a minimum (round-off)
  double lambda = 1e-3;
  Linearisation L = linearise(points, x);
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    const Mat3 A = L.J.transpose() * L.J;
    const Vec3 g = L.J.transpose() * L.r;
    bool accepted = false;
    Vec3 dx = Vec3::Zero();
    while (!accepted && lambda < lambda_give_up) {
      Mat3 M = A;
      M.diagonal() += lambda * A.diagonal();
      dx = M.ldlt().solve(g);
      const Vec3 trial = x + dx;
      if (dx.allFinite() && std::abs(trial[2]) < 700) {  // exp(ln I0) must stay finite
        Linearisation T = linearise(points, trial);
        if (std::isfinite(T.chi2) && T.chi2 <= L.chi2) {
          x = trial;
          L = std::move(T);
          lambda = std::max(lambda / 10, 1e-12);
          accepted = true;
          break;
        }
      }
      lambda *= 10;
    }
    if (!accepted) {
      fit.converged = true;
      fit.message = fmt::format("converged after {} iterations: no step lowers chi2 further",
                                iteration);
      break;
    }
    bool small = true;
    for (int i = 0; i < 3; ++i)
      small = small && std::abs(dx[i]) <= step_tolerance * std::max(std::abs(x[i]), 1e-3);
    if (small) {
      fit.converged = true;
      fit.message = fmt::format("converged after {} iterations: relative step below {:g}",
                                iteration + 1, step_tolerance);
      break;
    }
  }
  if (!fit.converged)
    fit.message = fmt::format("did not converge in {} iterations (chi2 = {:g})", max_iterations,
                              L.chi2);

  fit.mu_s = x[0];
  fit.mu_2 = x[1];
  fit.I0 = std::exp(x[2]);
  fit.chi2_per_dof = L.chi2 / dof;

  // Covariance (J^T W J)^-1 in (mu_s, mu_2, ln I0), mapped to (mu_s, mu_2, I0).
  const Mat3 A = L.J.transpose() * L.J;
  Eigen::LDLT<Mat3> ldlt(A);
  const bool positive = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                        (ldlt.vectorD().array() > 1e-14 * A.diagonal().maxCoeff()).all();
  if (!positive) {
    fit.converged = false;
    fit.message += "; J^T W J is singular: the points do not determine all three parameters "
                   "(measure on both sides of I0)";
  }
  Mat3 C = ldlt.solve(Mat3::Identity());
  const Eigen::DiagonalMatrix<double, 3> T(1.0, 1.0, fit.I0);  // dI0 = I0 d ln I0
  C = T * C * T;
  C = 0.5 * (C + C.transpose()).eval();  // exactly symmetric, not to round-off
  if (fit.chi2_per_dof > 1) C *= fit.chi2_per_dof;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) fit.covariance[i][j] = positive ? C(i, j) : NAN;
  fit.mu_s_err = std::sqrt(fit.covariance[0][0]);
  fit.mu_2_err = std::sqrt(fit.covariance[1][1]);
  fit.I0_err = std::sqrt(fit.covariance[2][2]);
  return fit;
}

PhiFit fit_phi_i(const std::vector<ShearPoint>& points) {
  check_points(points, "fit_phi_i", "phi", &ShearPoint::phi, &ShearPoint::phi_stderr, 3, 2,
               false);
  // Rows (1, -I_k) / se_k, right-hand side Phi_k / se_k: Phi = phi_max - a I is linear.
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const ShearPoint& p = points[static_cast<std::size_t>(k)];
    X(k, 0) = 1 / p.phi_stderr;
    X(k, 1) = -p.I / p.phi_stderr;
    y[k] = p.phi / p.phi_stderr;
  }
  const Eigen::Matrix2d A = X.transpose() * X;
  const Eigen::LDLT<Eigen::Matrix2d> ldlt(A);
  const Eigen::Vector2d b = ldlt.solve(X.transpose() * y);
  PhiFit fit;
  fit.points = static_cast<int>(n);
  fit.phi_max = b[0];
  fit.a = b[1];
  fit.chi2_per_dof = (y - X * b).squaredNorm() / static_cast<double>(n - 2);
  Eigen::Matrix2d C = ldlt.solve(Eigen::Matrix2d::Identity());
  if (fit.chi2_per_dof > 1) C *= fit.chi2_per_dof;
  fit.phi_max_err = std::sqrt(C(0, 0));
  fit.a_err = std::sqrt(C(1, 1));
  return fit;
}

}  // namespace grainlift
