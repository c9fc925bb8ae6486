// The small cylinder case the continuum tests share: D = 0.1 m in a 1 m x 1 m box symmetric
// about it, V = 0.1 m/s, no spin, P0 = 1000 Pa, Jop's mu(I) with the default regularisation,
// inertia off, refinement 1, sigma_n and sigma_t sampled at five angles.
#pragma once

#include <cmath>

#include "grainlift/continuum/continuum_config.h"

namespace grainlift::continuum::test {

inline ContinuumConfig coarse_case() {
  ContinuumConfig c;
  c.intruder_diameter = 0.1;
  c.half_width = 0.5;
  c.half_height = 0.5;
  c.intruder_velocity = {0.1, 0};
  c.ambient_pressure = 1000;
  c.refinement = 1;
  c.inertia = InertiaMode::off;
  c.surface_theta = {0.0, M_PI / 4, M_PI / 2, -M_PI / 2, M_PI};
  return c;
}

}  // namespace grainlift::continuum::test
