// The continuum's box from a case (continuum_box.h).
#include "continuum_box.h"

#include <fmt/format.h>

#include "grainlift/shared/case/case_geometry.h"
#include "grainlift/shared/errors.h"

namespace grainlift::continuum {

void set_box(const Case& c, ContinuumConfig& f) {
  const double D = c.intruder.diameter;
  if (c.continuum.box_half_size[0] > 0 && c.continuum.box_half_size[1] > 0) {
    f.far_field = FarField::symmetric_box;
    f.half_width = c.continuum.box_half_size[0];
    f.half_height = c.continuum.box_half_size[1];
    if (f.half_width <= D || f.half_height <= D)
      throw InputError(fmt::format(
          "{}: continuum.box_half_size = [{}, {}] m must exceed the intruder diameter {} m",
          c.source.path, f.half_width, f.half_height, D));
    return;
  }
  const std::string mode = continuum_far_field(c);
  if (c.intruder.velocity[1] != 0)
    throw InputError(fmt::format(
        "{}: the continuum solves the case's box with the intruder moving along x; intruder."
        "velocity = [{}, {}] m/s has a y part: set continuum.box_half_size for a box of the "
        "continuum's own",
        c.source.path, c.intruder.velocity[0], c.intruder.velocity[1]));
  const SolverBox b = solver_box(c);
  const auto& p = c.intruder.position;
  f.box_bottom = b.ymin - p[1];
  f.box_top = b.ymax - p[1];
  f.top = b.top == BoxEdge::free_surface ? TopEdge::free_surface : TopEdge::wall;
  // the DEM's settled bed (the loader keeps it above the intruder and inside the box)
  if (!std::isnan(c.continuum.bed_top)) f.box_top = c.continuum.bed_top - p[1];
  if (mode == "periodic") {
    if (b.left != BoxEdge::periodic)
      throw InputError(fmt::format(
          "{}: continuum.far_field = \"periodic\" needs a case periodic in x without side "
          "walls (domain.periodic[0] = true); use \"open\"",
          c.source.path));
    // the period centred on the intruder (the same periodic box, shifted)
    f.far_field = FarField::periodic;
    f.box_left = -0.5 * (b.xmax - b.xmin);
    f.box_right = 0.5 * (b.xmax - b.xmin);
  } else {
    f.far_field = FarField::open;
    const double up = c.continuum.open_length[0] * D, down = c.continuum.open_length[1] * D;
    const bool to_left = c.intruder.velocity[0] < 0;  // the medium comes from the left
    f.box_left = to_left ? -up : -down;
    f.box_right = to_left ? down : up;
  }
  // (validate_config refuses a box whose edges do not clear the intruder)
}

std::string box_statement(const Case& c, const ContinuumConfig& f) {
  const SolverBox b = solver_box(c);
  const double D = c.intruder.diameter;
  const auto& p = c.intruder.position;
  if (f.far_field == FarField::symmetric_box)
    return fmt::format(
        "warning: the FE box is not the DEM's: continuum.box_half_size gives [{:.4g}, {:.4g}] x "
        "[{:.4g}, {:.4g}] m about the intruder (u = -V on its inflow sides), where the grains "
        "fill [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] m",
        p[0] - f.half_width, p[0] + f.half_width, p[1] - f.half_height, p[1] + f.half_height,
        b.xmin, b.xmax, b.ymin, b.ymax);
  const double top = p[1] + f.box_top;
  const std::string edges = fmt::format(
      "bottom {} at y = {:.4g} m, top {} at y = {:.4g} m{}", box_edge_name(b.bottom), b.ymin,
      box_edge_name(b.top), top,
      top != b.ymax ? fmt::format(" (continuum.bed_top; the box's edge is at {:.4g} m)", b.ymax)
                    : std::string());
  // the DEM's run against its wake: which far field stands for its means
  const double wake_d = b.wake_travel / c.grains.diameter;
  const bool past_wake = c.dem.travel > wake_d;
  if (f.far_field == FarField::periodic)
    return fmt::format(
        "FE box = the DEM's: periodic in x with period {:.4g} m ({:.3g} D), {}{}",
        b.xmax - b.xmin, (b.xmax - b.xmin) / D, edges,
        past_wake ? std::string()
                  : fmt::format("; note: the DEM's {:g} d of travel stop before its wake at "
                                "{:.4g} d (its first crossing: continuum.far_field = \"open\")",
                                c.dem.travel, wake_d));
  std::string dem_x =
      b.left != BoxEdge::periodic
          ? fmt::format("the DEM's box spans x in [{:.4g}, {:.4g}] m", b.xmin, b.xmax)
      : past_wake
          ? fmt::format("note: the DEM's x is periodic ({:.3g} D) and its {:g} d of travel go "
                        "past its wake at {:.4g} d (its developed state: continuum.far_field "
                        "= \"periodic\")",
                        (b.xmax - b.xmin) / D, c.dem.travel, wake_d)
          : fmt::format("the DEM's x is periodic ({:.3g} D): this is its first crossing, "
                        "before the intruder meets its own wake after {:.4g} d of travel",
                        (b.xmax - b.xmin) / D, wake_d);
  return fmt::format("FE box: the DEM's walls ({}), open in x: {:.3g} D upstream and {:.3g} D "
                     "downstream of the intruder (continuum.open_length); {}",
                     edges, c.continuum.open_length[0], c.continuum.open_length[1], dem_x);
}

const char* far_field_name(FarField f) {
  switch (f) {
    case FarField::symmetric_box: return "symmetric_box";
    case FarField::periodic: return "periodic";
    case FarField::open: return "open";
  }
  return "?";
}

}  // namespace grainlift::continuum
