// Derived quantities of a result (derived_quantities.h).
#include "grainlift/shared/results/derived_quantities.h"

#include <cmath>

#include "grainlift/shared/surface/surface_stress.h"

namespace grainlift {

DerivedQuantities derive(const RunResult& r) {
  DerivedQuantities q;
  const Geometry& g = r.geometry;
  const double speed = std::hypot(g.velocity_x, g.velocity_y);
  q.spin_ratio = speed > 0 ? g.omega * 0.5 * g.intruder_diameter / speed : 0.0;
  if (r.means) {
    if (r.means->drag != 0) q.lift_over_drag = r.means->lift / r.means->drag;
    double gravity = g.reference_gravity;
    if (!(gravity > 0)) gravity = std::hypot(g.gravity_x, g.gravity_y);  // files before it
    if (gravity > 0) {
      const double b = g.bulk_density * gravity * 3.14159265358979323846 * g.intruder_diameter *
                       g.intruder_diameter / 4;
      q.buoyancy = b;
      q.lift_over_buoyancy = r.means->lift / b;
      if (g.equivalent_depth > 0)
        q.drag_coefficient =
            r.means->drag / (g.bulk_density * gravity * g.equivalent_depth * g.intruder_diameter);
    }
  }
  if (r.surface && !r.surface->sigma_n.empty()) {
    symmetry_split(r.surface->sigma_n, q.sigma_n_symmetric, q.sigma_n_antisymmetric);
    symmetry_split(r.surface->sigma_t, q.sigma_t_symmetric, q.sigma_t_antisymmetric);
  }
  return q;
}

}  // namespace grainlift
