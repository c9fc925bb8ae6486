// The nonlocal fluidity model's cooperativity length and local fluidity (fluidity_law.h).
#include "grainlift/shared/rheology/fluidity_law.h"

#include <algorithm>
#include <cmath>

namespace grainlift {

double cooperativity_length(double mu, double mu_s, double A, double d, double xi_max) {
  const double length = A * d;
  const double eps = (length / xi_max) * (length / xi_max);
  const double dmu = mu - mu_s;
  return length / std::sqrt(std::sqrt(dmu * dmu + eps * eps));
}

namespace {
/// The cap of the local fluidity's inertial number, min(1, 999 I0).
double inertial_cap(const FluidityMaterial& r) {
  return std::min(kMaxLocalFluidityInertial, 0.999 * 1e3 * r.I0);
}
/// Jop's mu(I).
double jop_mu(double I, const FluidityMaterial& r) {
  return r.mu_s + (r.mu_2 - r.mu_s) * I / (I + r.I0);
}
}  // namespace

double local_fluidity(double mu, double p, const FluidityMaterial& r) {
  if (!(p > 0) || !(mu > r.mu_s)) return 0;
  const double I_cap = inertial_cap(r);
  const double mu_cap = jop_mu(I_cap, r);
  const double m = std::min(mu, mu_cap);
  const double I = r.I0 * (m - r.mu_s) / (r.mu_2 - m);
  return I * std::sqrt(p / r.solid_density) / (r.grain_diameter * m);
}

FluidityStressRatio stress_ratio_at_fluidity(double rate, double p, double excess,
                                             const FluidityMaterial& r) {
  FluidityStressRatio out;
  if (!(rate > 0) || !(p > 0)) return out;
  const double S = std::sqrt(p / r.solid_density) / r.grain_diameter;  // gamma_dot = S I
  const double I_cap = inertial_cap(r);
  const double mu_cap = jop_mu(I_cap, r);
  const double g_cap = S * I_cap / mu_cap;  // g_loc at and above mu_cap
  if (excess > 0 && rate <= excess * r.mu_s) {  // below yield: only the excess flows
    out.mu = rate / excess;
    out.dmu_drate = 1 / excess;
    return out;
  }
  if (rate >= mu_cap * (g_cap + excess)) {  // above the cap: g_loc = g_cap (~ sqrt p)
    const double g = g_cap + excess;
    if (!(g > 0)) return out;
    out.mu = rate / g;
    out.dmu_drate = 1 / g;
    out.dmu_dp = -out.mu / g * g_cap / (2 * p);
    return out;
  }
  // Jop's branch: F(I) = S I + excess mu(I) - rate = 0 on (0, I_cap), F < 0 at 0 (the first
  // branch is passed) and > 0 at I_cap; F rises wherever it is positive
  const double a = (r.mu_2 - r.mu_s) * r.I0;  // mu'(I) = a / (I + I0)^2
  double lo = 0, hi = I_cap, I = std::min(rate / S, 0.5 * I_cap);
  for (int it = 0; it < 200; ++it) {
    const double F = S * I + excess * jop_mu(I, r) - rate;
    if (F < 0) lo = I; else hi = I;
    const double dF = S + excess * a / ((I + r.I0) * (I + r.I0));
    double next = dF > 0 ? I - F / dF : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - I) <= 1e-15 * I_cap;
    I = next;
    if (done || hi - lo <= 1e-15 * I_cap) break;
  }
  const double mu_I = a / ((I + r.I0) * (I + r.I0));
  const double dF = S + excess * mu_I;
  out.mu = jop_mu(I, r);
  out.dmu_drate = mu_I / dF;
  out.dmu_dp = -mu_I * (S / (2 * p)) * I / dF;
  return out;
}

}  // namespace grainlift
