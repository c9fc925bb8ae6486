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

double local_fluidity(double mu, double p, const FluidityMaterial& r) {
  if (!(p > 0) || !(mu > r.mu_s)) return 0;
  const double I_cap = std::min(kMaxLocalFluidityInertial, 0.999 * 1e3 * r.I0);
  const double mu_cap = r.mu_s + (r.mu_2 - r.mu_s) * I_cap / (I_cap + r.I0);  // mu(I_cap)
  const double m = std::min(mu, mu_cap);
  const double I = r.I0 * (m - r.mu_s) / (r.mu_2 - m);
  return I * std::sqrt(p / r.solid_density) / (r.grain_diameter * m);
}

}  // namespace grainlift
