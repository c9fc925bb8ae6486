// Smoothing of a pointwise surface trace (the continuum's sigma_n(theta), sigma_t(theta)) with
// the Gaussian kernel that the DEM's SurfaceStressEstimator applies to its contacts, so that
// both solvers' /surface distributions are the same average of the traction (Guillard,
// Forterre & Pouliquen 2014, eq. (A4)).
//
// A trace sigma(theta) sampled at angles theta_j, each standing for the arc dtheta_j, is the
// set of point forces f_j = sigma(theta_j) R dtheta_j (N/m). Eq. (A4) with the estimator's
// normalisation (surface_stress.h) turns them into
//     sigma~(theta_m) = sum_j g_s(theta_m - theta_j) sigma(theta_j) dtheta_j,
//     g_s(d) = exp(-d^2 / (2 s^2)) / (sqrt(2 pi) s),   d wrapped to (-pi, pi],
// the midpoint rule for the periodic convolution of sigma with a kernel of unit integral: a
// constant stays constant and the k-th Fourier mode is multiplied by exp(-k^2 s^2 / 2)
// (kernel_attenuation), up to the quadrature error below.
//
// Quadrature error. On an even grid of N angles the rule multiplies mode k by
// sum_n exp(-(k + n N)^2 s^2 / 2) instead (Poisson summation): for a smooth trace the error is
// about 2 exp(-(N - k)^2 s^2 / 2), 5e-17 for N = 64, s = 8 deg, k = 2. The continuum's trace
// is only continuous (a Q2 trace with kinks at the face vertices), its modes decay like
// 1/k^2, and modes near N fold back onto low modes undamped; so the continuum glue samples
// it on a finer grid (an oversampled list of angles) and smooths from there onto the M-grid.
#pragma once

#include <vector>

namespace grainlift {

/// @brief sigma~(theta_m) at the M angles of surface_angle_grid(M) from a trace given at
/// arbitrary distinct angles: sum_j g_s(theta_m - theta_j) f_j dtheta_j (Guillard eq. (A4),
/// normalisation of SurfaceStressEstimator), dtheta_j half the periodic distance between the
/// neighbours of theta_j (2 pi / N on an even grid of N angles).
/// @param theta angles of the samples (rad, from V, counter-clockwise; any period, any order)
/// @param values the trace at those angles (Pa)
/// @param M number of output angles theta_m = (m + 1/2) 2 pi / M
/// @param width_deg Gaussian standard deviation s (deg), > 0
/// @return the smoothed trace on the M-grid (Pa)
std::vector<double> smooth_onto_grid(const std::vector<double>& theta,
                                     const std::vector<double>& values, int M, double width_deg);

/// @brief smooth_onto_grid from the grid theta_m of @p values onto itself: the kernel of
/// Guillard eq. (A4) applied to a trace sampled on the shared grid (M = values.size()).
/// Accurate when the trace's modes near M are negligible (see the file comment);
/// @p width_deg = 0 returns @p values unchanged (the kernel's pointwise limit).
/// @param values the trace at theta_m (Pa); @param width_deg Gaussian standard deviation (deg)
std::vector<double> smooth_on_grid(const std::vector<double>& values, double width_deg);

}  // namespace grainlift
