#include "grainlift/shared/case/case_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

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
  g.nx = std::max(
      1, int(std::ceil(2 * c.output.field_half_size[0] * c.intruder.diameter / g.spacing)));
  g.ny = std::max(
      1, int(std::ceil(2 * c.output.field_half_size[1] * c.intruder.diameter / g.spacing)));
  g.x0 = -0.5 * g.nx * g.spacing;
  g.y0 = -0.5 * g.ny * g.spacing;
  return g;
}

const char* box_edge_name(BoxEdge e) {
  switch (e) {
    case BoxEdge::wall: return "wall";
    case BoxEdge::lid: return "lid";
    case BoxEdge::free_surface: return "free surface";
    case BoxEdge::periodic: return "periodic";
    case BoxEdge::open: return "open";
  }
  return "?";
}

SolverBox solver_box(const Case& c) {
  const auto& d = c.domain;
  const double dg = c.grains.diameter;
  SolverBox b;
  // the DEM's wall disks have their centres half a grain inside the box edge (make_wall_disks):
  // the medium ends at their inner edge, one grain diameter inside
  b.xmin = d.x_range[0] + (d.wall_left ? dg : 0.0);
  b.xmax = d.x_range[1] - (d.wall_right ? dg : 0.0);
  b.ymin = d.y_range[0] + (d.wall_bottom ? dg : 0.0);
  b.ymax = d.y_range[1] - (d.wall_top ? dg : 0.0);
  const auto side = [](bool periodic, bool wall) {
    return periodic ? BoxEdge::periodic : wall ? BoxEdge::wall : BoxEdge::open;
  };
  b.left = side(d.periodic[0] && !d.wall_left, d.wall_left);
  b.right = side(d.periodic[0] && !d.wall_right, d.wall_right);
  b.bottom = side(d.periodic[1] && !d.wall_bottom, d.wall_bottom);
  b.top = side(d.periodic[1] && !d.wall_top, d.wall_top);
  if (b.top == BoxEdge::wall && d.lid_pressure > 0) b.top = BoxEdge::lid;
  if (b.top == BoxEdge::open && c.scene.gravity[1] < 0 && c.scene.gravity[0] == 0)
    b.top = BoxEdge::free_surface;
  const bool along_x = c.intruder.velocity[1] == 0 && c.intruder.velocity[0] != 0;
  b.wake_travel = (b.left == BoxEdge::periodic && along_x)
                      ? (d.x_range[1] - d.x_range[0]) - c.intruder.diameter
                      : std::numeric_limits<double>::infinity();
  return b;
}

std::string continuum_far_field(const Case& c) {
  if (c.continuum.far_field != "auto") return c.continuum.far_field;
  const SolverBox b = solver_box(c);
  if (b.left != BoxEdge::periodic) return "open";
  if (c.speed() == 0) return "periodic";
  return c.dem.travel * c.grains.diameter > b.wake_travel ? "periodic" : "open";
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
