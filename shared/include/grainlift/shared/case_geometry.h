// What both solvers' glue derives from a case in the same way: the shared field grid in the
// intruder frame and the /geometry block of the output file.
#pragma once

#include <vector>

#include "grainlift/shared/case_model.h"
#include "grainlift/shared/run_result.h"

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

/// The /geometry block: intruder, grains, kinematics and gravity from the case; the domain is
/// the case's box (a solver with its own box overwrites domain_*); pressure_scale left 0 for
/// the solver to state.
Geometry case_geometry(const Case& c);

}  // namespace grainlift
