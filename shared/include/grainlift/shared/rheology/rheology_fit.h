// Calibration of the continuum's friction law on DEM grains: weighted least-squares fits of
// mu(I) (Jop, Forterre & Pouliquen, Nature 441, 2006) and of the dilatancy law Phi(I) to
// points measured in a steady simple-shear cell. Pure functions, no I/O.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace grainlift {

/// One steady simple-shear measurement (all dimensionless).
struct ShearPoint {
  double I = 0;           ///< inertial number I = gamma_dot d / sqrt(P / rho_s), > 0
  double mu = 0;          ///< friction coefficient tau / P
  double mu_stderr = 0;   ///< standard error of mu, > 0
  double phi = 0;         ///< area (solid) fraction Phi
  double phi_stderr = 0;  ///< standard error of Phi, > 0
};

/// Fitted mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1) with its uncertainties.
struct MuIFit {
  double mu_s = 0, mu_2 = 0, I0 = 0;              ///< best-fit parameters (dimensionless)
  double mu_s_err = 0, mu_2_err = 0, I0_err = 0;  ///< one-sigma uncertainties (sqrt of diag)
  /// Covariance of (mu_s, mu_2, I0), in that order (see fit_mu_i for the chi2/dof scaling).
  std::array<std::array<double, 3>, 3> covariance{};
  double chi2_per_dof = 0;  ///< sum_k ((mu_k - mu(I_k)) / se_k)^2 / (points - 3)
  int points = 0;           ///< number of points used
  bool converged = false;   ///< false: the parameters are the last iterate, do not use them
  std::string message;      ///< how the iteration ended (iterations, reason)
};

/// @brief Weighted nonlinear least squares of Jop's mu(I) law to @p points.
///
/// Minimises chi2 = sum_k ((mu_k - mu(I_k)) / mu_stderr_k)^2 over (mu_s, mu_2, ln I0) with
/// Levenberg-Marquardt (Marquardt's diagonal scaling); fitting ln I0 keeps I0 > 0. Start values
/// come from the data: mu_s = smallest mu, mu_2 = largest mu + 10 % of the spread, I0 = median I.
/// The covariance is (J^T W J)^-1 at the optimum, W = diag(1 / mu_stderr^2), mapped from ln I0
/// to I0 (dI0 = I0 d ln I0). When chi2/dof > 1 the covariance is multiplied by chi2/dof (the
/// stated errors were too small to explain the scatter); when chi2/dof <= 1 it is left as is.
/// @param points >= 4 points with I > 0, mu_stderr > 0, finite values, at least 3 distinct I
///        (the law has 3 parameters); ideally spanning I0 (a decade or more on each side).
/// @throws std::invalid_argument on too few points, non-positive errors or non-finite values.
MuIFit fit_mu_i(const std::vector<ShearPoint>& points);

/// Fitted linear dilatancy law Phi(I) = phi_max - a I with its uncertainties.
struct PhiFit {
  double phi_max = 0, a = 0;          ///< Phi at I -> 0 (-), slope (-)
  double phi_max_err = 0, a_err = 0;  ///< one-sigma uncertainties
  double chi2_per_dof = 0;            ///< sum_k ((Phi_k - Phi(I_k)) / se_k)^2 / (points - 2)
  int points = 0;                     ///< number of points used
};

/// @brief Weighted linear least squares of Phi = phi_max - a I to @p points (weights
/// 1 / phi_stderr^2). Covariance (X^T W X)^-1, multiplied by chi2/dof when chi2/dof > 1.
/// @param points >= 3 points with I >= 0, phi_stderr > 0, finite values, at least 2 distinct I.
/// @throws std::invalid_argument on too few points, non-positive errors or non-finite values.
PhiFit fit_phi_i(const std::vector<ShearPoint>& points);

/// @brief Jop's mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1) (Jop, Forterre & Pouliquen 2006).
/// @param I inertial number (>= 0); mu_s, mu_2, I0 dimensionless (I0 > 0).
double jop_mu(double I, double mu_s, double mu_2, double I0);

}  // namespace grainlift
