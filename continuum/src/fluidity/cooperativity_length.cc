// The capped cooperativity length (see cooperativity_length.h for the cap rule).
#include "grainlift/continuum/fluidity/cooperativity_length.h"

#include <cmath>

namespace grainlift::continuum::fluidity {

double xi_of_mu(double mu, double mu_s, double A, double d, double xi_max) {
  // Henann & Kamrin 2013: xi = A d / sqrt|mu - mu_s|, smoothed on (mu - mu_s)^2
  const double length = A * d;
  const double eps = (length / xi_max) * (length / xi_max);
  const double dmu = mu - mu_s;
  return length / std::sqrt(std::sqrt(dmu * dmu + eps * eps));
}

}  // namespace grainlift::continuum::fluidity
