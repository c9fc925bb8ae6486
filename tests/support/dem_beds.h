// The small walled bed the DEM tests start from: W x H mean grain diameters centred on the
// origin, frozen-disk walls top and bottom, periodic in x, area fraction Phi, an intruder of
// 5 d moving at 1 m/s along +x. Each test sets what it varies on top of it.
#pragma once

#include "grainlift/dem/dem_config.h"

namespace grainlift::test_support {

inline dem::DemConfig walled_bed(double w, double h, double phi) {
  dem::DemConfig c;
  const double d = c.grain_diameter;
  c.xmin = -0.5 * w * d;
  c.xmax = 0.5 * w * d;
  c.ymin = -0.5 * h * d;
  c.ymax = 0.5 * h * d;
  c.wall_bottom = c.wall_top = true;
  c.area_fraction = phi;
  c.intruder_diameter = 5 * d;
  c.intruder_velocity = {1.0, 0.0};
  return c;
}

}  // namespace grainlift::test_support
