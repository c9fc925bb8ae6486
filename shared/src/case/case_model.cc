#include "grainlift/shared/case/case_model.h"

#include <cmath>

namespace grainlift {

double Case::speed() const { return std::hypot(intruder.velocity[0], intruder.velocity[1]); }

double Case::spin_ratio() const { return intruder.omega * 0.5 * intruder.diameter / speed(); }

double Case::lithostatic_pressure() const {
  const double g = std::hypot(scene.gravity[0], scene.gravity[1]);
  // Depth measured against gravity: distance from the intruder centre to the box edge that
  // gravity points away from (the free surface or the top of the bed).
  double depth = 0;
  if (g > 0) {
    const double ux = -scene.gravity[0] / g, uy = -scene.gravity[1] / g;  // "up"
    // project the box corners on "up"; the top of the bed is the largest projection
    double top = -1e300;
    for (double x : {domain.x_range[0], domain.x_range[1]})
      for (double y : {domain.y_range[0], domain.y_range[1]}) top = std::max(top, x * ux + y * uy);
    depth = top - (intruder.position[0] * ux + intruder.position[1] * uy);
  }
  return bulk_density() * g * depth;
}

double Case::reference_gravity() const {
  const double g = std::hypot(scene.gravity[0], scene.gravity[1]);
  return g > 0 ? g : scene.lid_gravity;
}

double Case::equivalent_depth() const {
  const double rho_g = bulk_density() * reference_gravity();
  return rho_g > 0 ? stated_pressure() / rho_g : 0.0;
}

}  // namespace grainlift
