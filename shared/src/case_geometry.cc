#include "grainlift/shared/case_geometry.h"

#include <algorithm>
#include <cmath>

namespace grainlift {

namespace {
std::vector<double> centres(double origin, double h, int n) {
  std::vector<double> v(std::size_t(std::max(n, 0)));
  for (int i = 0; i < n; ++i) v[std::size_t(i)] = origin + (i + 0.5) * h;
  return v;
}
}  // namespace

std::vector<double> FieldGridLayout::x_centres() const { return centres(x0, spacing, nx); }
std::vector<double> FieldGridLayout::y_centres() const { return centres(y0, spacing, ny); }

FieldGridLayout field_grid_layout(const Case& c) {
  FieldGridLayout g;
  if (!c.output.fields) return g;
  g.enabled = true;
  g.spacing = c.output.field_spacing * c.grains.diameter;
  g.nx = std::max(1, int(std::ceil(2 * c.output.field_half_size[0] * c.intruder.diameter / g.spacing)));
  g.ny = std::max(1, int(std::ceil(2 * c.output.field_half_size[1] * c.intruder.diameter / g.spacing)));
  g.x0 = -0.5 * g.nx * g.spacing;
  g.y0 = -0.5 * g.ny * g.spacing;
  return g;
}

Geometry case_geometry(const Case& c) {
  Geometry q;
  q.intruder_diameter = c.intruder.diameter;
  q.intruder_x = c.intruder.position[0];
  q.intruder_y = c.intruder.position[1];
  q.grain_diameter = c.grains.diameter;
  q.domain_xmin = c.domain.x_range[0];
  q.domain_xmax = c.domain.x_range[1];
  q.domain_ymin = c.domain.y_range[0];
  q.domain_ymax = c.domain.y_range[1];
  q.velocity_x = c.intruder.velocity[0];
  q.velocity_y = c.intruder.velocity[1];
  q.omega = c.intruder.omega;
  q.gravity_x = c.scene.gravity[0];
  q.gravity_y = c.scene.gravity[1];
  q.bulk_density = c.bulk_density();
  q.reference_gravity = c.reference_gravity();
  q.equivalent_depth = c.equivalent_depth();
  return q;
}

}  // namespace grainlift
