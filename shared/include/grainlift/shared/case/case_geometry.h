// What both solvers' glue derives from a case in the same way: the shared field grid in the
// intruder frame and the /geometry block of the output file.
#pragma once

#include <string>
#include <vector>

#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/results/run_result.h"

namespace grainlift {

/// The shared Cartesian grid in the intruder frame: square cells of output.field_spacing mean
/// grain diameters covering +- output.field_half_size intruder diameters, centred on the
/// intruder. Cell (i, j) spans [x0 + i h, x0 + (i+1) h] x [y0 + j h, y0 + (j+1) h].
struct FieldGridLayout {
  bool enabled = false;
  double x0 = 0, y0 = 0, spacing = 0;  ///< m
  int nx = 0, ny = 0;
  /// Cell-centre coordinates (m, relative to the intruder centre).
  std::vector<double> x_centres() const;
  std::vector<double> y_centres() const;
};
FieldGridLayout field_grid_layout(const Case& c);

/// How an edge of the box bounds the medium, for both solvers.
enum class BoxEdge {
  wall,          ///< a wall of frozen grains (the FE: no slip at the wall's lab-frame velocity)
  lid,           ///< the top wall as a lid at domain.lid_pressure (rigid or free disks)
  free_surface,  ///< no wall, gravity pointing away from it: the bed's own top (traction free)
  periodic,      ///< a periodic direction
  open           ///< no wall and no periodicity: the box edge is far field
};
const char* box_edge_name(BoxEdge e);

/// The box the grains fill, in the lab frame: the one domain both solvers solve. Its edges are
/// where the DEM's medium ends: the inner edge of the frozen wall disks (a grain diameter
/// inside domain.x_range / y_range), the case's edge on a periodic or open side, and the top
/// of the box for a free surface (docs/crosscheck.md, "One box").
struct SolverBox {
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  ///< m
  BoxEdge left = BoxEdge::open, right = BoxEdge::open, bottom = BoxEdge::open,
          top = BoxEdge::open;
  /// m: the intruder's travel before its front reaches the bed its back left at the start
  /// (box length less D along a periodic x); infinite when x is not periodic or V has a y part
  double wake_travel = 0;
};
SolverBox solver_box(const Case& c);

/// The continuum's far field, from continuum.far_field: "periodic" (the case's x period: the
/// DEM's developed state after many crossings) or "open" (inflow of undisturbed bed, outflow
/// at the ends of a long box: the DEM's first crossing). "auto" takes periodic when the case
/// is periodic in x, V is along x and the DEM's run reaches its own wake (dem.travel d >
/// SolverBox::wake_travel); open otherwise.
std::string continuum_far_field(const Case& c);

/// The /geometry block: intruder, grains, kinematics and gravity from the case; the domain is
/// the case's box (a solver with its own box overwrites domain_*); pressure_scale left 0 for
/// the solver to state.
Geometry case_geometry(const Case& c);

}  // namespace grainlift
