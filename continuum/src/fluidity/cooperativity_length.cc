// The capped cooperativity length (see cooperativity_length.h for the cap rule): the shared law.
#include "grainlift/continuum/fluidity/cooperativity_length.h"

#include "grainlift/shared/rheology/fluidity_law.h"

namespace grainlift::continuum::fluidity {

double xi_of_mu(double mu, double mu_s, double A, double d, double xi_max) {
  return grainlift::cooperativity_length(mu, mu_s, A, d, xi_max);
}

}  // namespace grainlift::continuum::fluidity
