// The cooperativity amplitude A from a sheared layer's velocity profile (cooperativity_fit.h).
#include "grainlift/shared/rheology/cooperativity_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grainlift {

namespace {

constexpr int kCellsPerDiameter = 32;

/// The least-squares line p = a + b y through the bins (the pressure under uniform weight).
struct Line {
  double a = 0, b = 0;
};
Line pressure_line(const CreepProfile& pr) {
  const double n = double(pr.y.size());
  double sy = 0, sp = 0, syy = 0, syp = 0;
  for (std::size_t k = 0; k < pr.y.size(); ++k)
    sy += pr.y[k], sp += pr.pressure[k], syy += pr.y[k] * pr.y[k], syp += pr.y[k] * pr.pressure[k];
  const double b = (n * syp - sy * sp) / (n * syy - sy * sy);
  return {(sp - b * sy) / n, b};
}

/// The bins that are fitted.
std::vector<std::size_t> fitted_bins(const CreepProfile& p) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < p.y.size(); ++k)
    if (p.y[k] >= p.y_min && p.y[k] <= p.y_max) out.push_back(k);
  return out;
}

struct Result {
  double chi2 = 0, scale = 0, floor = 0;
};

/// chi2 of the best v = v_floor + C model over the fitted bins.
Result chi2_of(const CreepProfile& p, const std::vector<std::size_t>& bins,
               const std::vector<double>& model) {
  double sw = 0, sf = 0, sv = 0, sff = 0, sfv = 0;
  for (std::size_t k : bins) {
    const double w = 1.0 / (p.vx_err[k] * p.vx_err[k]), f = model[k], v = p.vx[k];
    sw += w, sf += w * f, sv += w * v, sff += w * f * f, sfv += w * f * v;
  }
  Result r;
  r.scale = (sw * sfv - sf * sv) / (sw * sff - sf * sf);
  r.floor = (sv - r.scale * sf) / sw;
  for (std::size_t k : bins)
    r.chi2 += std::pow((p.vx[k] - r.floor - r.scale * model[k]) / p.vx_err[k], 2);
  return r;
}

/// One fit at the given law (mu_s) and tau; amplitude_err holds the profile's error only.
CooperativityFit fit_once(CreepProfile p, const FluidityMaterial& law, double tau,
                          const CooperativityFitOptions& o) {
  p.shear_stress = tau;
  const std::vector<std::size_t> bins = fitted_bins(p);
  const auto fit_at = [&](double x) {
    return chi2_of(p, bins, fluidity_velocity(p, law, std::exp(x), o.xi_max));
  };
  const auto chi2 = [&](double x) { return fit_at(x).chi2; };
  CooperativityFit f;
  f.points = int(bins.size());
  f.mu_min = tau / p.pressure[bins.front()];  // the bottom: the largest pressure
  f.mu_max = tau / p.pressure[bins.back()];
  constexpr int kScan = 120;
  const double lo = std::log(o.a_min), hi = std::log(o.a_max), h = (hi - lo) / kScan;
  int best = 0;
  double best_chi2 = chi2(lo);
  for (int i = 1; i <= kScan; ++i) {
    const double c = chi2(lo + i * h);
    if (c < best_chi2) best = i, best_chi2 = c;
  }
  double x = lo + best * h;
  if (best > 0 && best < kScan) {  // golden section on the bracket of the best scan point
    const double gr = 0.5 * (std::sqrt(5.0) - 1);
    double a = x - h, b = x + h, x1 = b - gr * (b - a), x2 = a + gr * (b - a);
    double f1 = chi2(x1), f2 = chi2(x2);
    for (int it = 0; it < 50; ++it) {  // one new chi2 per step
      if (f1 < f2) {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - gr * (b - a), f1 = chi2(x1);
      } else {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + gr * (b - a), f2 = chi2(x2);
      }
    }
    x = 0.5 * (a + b);
  }
  const Result r = fit_at(x);
  f.chi2_per_dof = r.chi2 / double(f.points - 3);
  f.scale = r.scale;
  f.floor = r.floor;
  // one sigma: where chi2 rises by max(1, chi2/dof) (errors scaled when they are too small)
  const double rise = r.chi2 + std::max(1.0, f.chi2_per_dof);
  bool bounded = true;
  const auto edge = [&](double step) {
    double y = x;
    while (chi2(y + step) < rise) {
      y += step;
      if (y < lo || y > hi) {
        bounded = false;
        break;
      }
    }
    return std::exp(y + 0.5 * step);
  };
  f.amplitude = std::exp(x);
  const double upper = edge(0.005);
  if (best == 0) {
    f.upper_bound = upper;
    f.message = "chi2 is least at A = " + std::to_string(o.a_min) +
                ", the local limit: A < " + std::to_string(upper) + " (one sigma)";
    return f;
  }
  const double lower = edge(-0.005);
  f.profile_err = 0.5 * (upper - lower);
  f.amplitude_err = f.profile_err;
  if (!bounded || best == kScan) {
    f.message = "chi2 stays within one sigma of its least out to the end of A's range [" +
                std::to_string(o.a_min) + ", " + std::to_string(o.a_max) +
                "]: A is not determined (average longer)";
    return f;
  }
  f.ok = true;
  return f;
}

}  // namespace

std::vector<double> fluidity_velocity(const CreepProfile& p, const FluidityMaterial& law,
                                      double A, double xi_max) {
  if (!(xi_max > 0)) xi_max = p.top - p.bottom;
  const double d = law.grain_diameter, tau = p.shear_stress;
  const int n = std::max(8, int(std::ceil((p.top - p.bottom) / d * kCellsPerDiameter)));
  const double h = (p.top - p.bottom) / n;
  const Line line = pressure_line(p);
  // g - xi^2 g'' = g_loc, second-order differences, g' = 0 at both ends (ghost nodes)
  std::vector<double> mu(n + 1), lower(n + 1), diag(n + 1), upper(n + 1), rhs(n + 1), g(n + 1);
  for (int i = 0; i <= n; ++i) {
    const double y = p.bottom + i * h, pressure = std::max(line.a + line.b * y, 1e-12);
    mu[i] = tau / pressure;
    const double xi = cooperativity_length(mu[i], law.mu_s, A, d, xi_max);
    const double c = xi * xi / (h * h);
    lower[i] = upper[i] = -c;
    diag[i] = 1 + 2 * c;
    rhs[i] = local_fluidity(mu[i], pressure, law);
  }
  upper[0] *= 2, lower[n] *= 2;
  for (int i = 1; i <= n; ++i) {  // Thomas algorithm
    const double m = lower[i] / diag[i - 1];
    diag[i] -= m * upper[i - 1];
    rhs[i] -= m * rhs[i - 1];
  }
  g[n] = rhs[n] / diag[n];
  for (int i = n - 1; i >= 0; --i) g[i] = (rhs[i] - upper[i] * g[i + 1]) / diag[i];
  std::vector<double> v(n + 1, 0.0);  // v = integral of gamma_dot = mu g
  for (int i = 1; i <= n; ++i) v[i] = v[i - 1] + 0.5 * h * (mu[i - 1] * g[i - 1] + mu[i] * g[i]);
  // each bin's mean: the exact average of the piecewise-linear v over the bin
  std::vector<double> W(n + 1, 0.0);  // integral of v from the bottom to node i
  for (int i = 1; i <= n; ++i) W[i] = W[i - 1] + 0.5 * h * (v[i - 1] + v[i]);
  const auto integral_to = [&](double y) {
    const double t = std::clamp((y - p.bottom) / h, 0.0, double(n));
    const int i = std::min(n - 1, int(t));
    const double s = t - i;
    return W[i] + h * (v[i] * s + 0.5 * (v[i + 1] - v[i]) * s * s);
  };
  const double half = p.y.size() > 1 ? 0.5 * (p.y[1] - p.y[0]) : 0.5 * d;
  std::vector<double> out(p.y.size(), 0.0);
  for (std::size_t k = 0; k < p.y.size(); ++k)
    out[k] = (integral_to(p.y[k] + half) - integral_to(p.y[k] - half)) / (2 * half);
  return out;
}

CooperativityFit fit_cooperativity(const CreepProfile& p, const FluidityMaterial& law,
                                   double mu_s_err, const CooperativityFitOptions& o) {
  const std::size_t n = p.y.size();
  if (p.vx.size() != n || p.vx_err.size() != n || p.pressure.size() != n)
    throw std::invalid_argument("fit_cooperativity: y, vx, vx_err and pressure differ in length");
  if (!(law.mu_s >= 0 && law.mu_s < law.mu_2) || !(law.I0 > 0) || !(law.solid_density > 0) ||
      !(law.grain_diameter > 0) || !(mu_s_err >= 0))
    throw std::invalid_argument("fit_cooperativity: need 0 <= mu_s < mu_2, I0, rho_s, d > 0, "
                                "mu_s_err >= 0");
  if (!(p.top > p.bottom) || !(p.shear_stress > 0) || !(o.a_min > 0 && o.a_max > o.a_min))
    throw std::invalid_argument("fit_cooperativity: need top > bottom, tau > 0, "
                                "0 < a_min < a_max");
  const std::vector<std::size_t> bins = fitted_bins(p);
  if (bins.size() < 5)
    throw std::invalid_argument("fit_cooperativity: " + std::to_string(bins.size()) +
                                " bins between y_min and y_max; the fit needs 5");
  for (std::size_t k : bins)
    if (!(p.vx_err[k] > 0))
      throw std::invalid_argument("fit_cooperativity: a fitted bin has no velocity error");
  CooperativityFit f = fit_once(p, law, p.shear_stress, o);
  if (f.ok && !(f.scale > 1 / o.scale_range && f.scale < o.scale_range)) {
    f.ok = false;
    f.message = "the layer flows at " + std::to_string(f.scale) + " x the calibrated mu(I)'s "
                "velocity (accepted 1/" + std::to_string(o.scale_range) + " to " +
                std::to_string(o.scale_range) + "): the law does not hold in this cell, A is "
                "not determined (a slower lid, or a mu(I) measured over the layer's I)";
  }
  if (!f.ok) return f;
  // the errors of mu_s and tau, each by refitting at +- one sigma (half the change of A)
  const auto spread = [&](double dmu, double dtau) {
    FluidityMaterial lo = law, hi = law;
    lo.mu_s -= dmu, hi.mu_s += dmu;
    const CooperativityFit a = fit_once(p, lo, p.shear_stress - dtau, o);
    const CooperativityFit b = fit_once(p, hi, p.shear_stress + dtau, o);
    return a.ok && b.ok ? 0.5 * std::abs(b.amplitude - a.amplitude) : f.amplitude;
  };
  f.mu_s_err_part = spread(mu_s_err, 0);
  const double tau_part = spread(0, p.shear_stress_err);
  f.amplitude_err = std::sqrt(f.profile_err * f.profile_err + f.mu_s_err_part * f.mu_s_err_part +
                              tau_part * tau_part);
  return f;
}

}  // namespace grainlift
