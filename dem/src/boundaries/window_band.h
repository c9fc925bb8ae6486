// The co-moving window's pull on one grain (DemSystem::set_window): the acceleration that a
// band across the box adds to the grains inside it, a spring to each grain's site and a drag,
// both ramped from zero at the band's edges. Evaluated before each kick for the grains
// update_window() flagged (DemSystem::window_forces, comoving_window.cc).
#pragma once

#include <cmath>
#include <cstdint>

#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem::detail {

struct WindowBand {
  double centre = 0;      ///< m, x of the band's middle
  double half = 0;        ///< m, half its width
  double inv_half = 0;    ///< 1 / half (1/m)
  double rate = 0;        ///< 1/s
  const double* site_x = nullptr;
  const double* site_y = nullptr;
  /// per layer: where its sites are now (m: the slide at the matching and the layer's velocity
  /// times the time since, wrapped into the box once per layer: window_forces) and the layer's
  /// velocity (m/s; the drag acts on v - vel)
  const double* shift_x = nullptr;
  const double* shift_y = nullptr;
  const double* vel_x = nullptr;
  const double* vel_y = nullptr;
  const std::int32_t* layer = nullptr;  ///< per grain
  const int* target = nullptr;  ///< per grain: its site or -1
  PeriodicBox box;

  /// The band's pull on grain @p i at (x, y) moving at (vx, vy, w), into (ax, ay, alpha);
  /// false (and nothing written) outside the band:
  /// with s = (1 - u^2)^2, u = (x - centre) / half in (-1, 1), a = -s rate^2 (x - site -
  /// shift) - 2 sqrt(s) rate (v - vel) with the grain's layer's shift and vel (critically
  /// damped at every u), alpha = -2 sqrt(s) rate w. The ramp is zero with a finite slope at
  /// the edges, one in the middle (a polynomial: no transcendental per grain and step).
  /// @p weight: s, the ramp.
  inline bool pull(int i, double x, double y, double vx, double vy, double w, double& ax,
                   double& ay, double& alpha, double& weight) const {
    double dx = x - centre, dy0 = 0;
    box.min_image(dx, dy0);
    if (!(std::fabs(dx) < half)) return false;
    const double u = dx * inv_half;
    const double root = 1.0 - u * u;  // sqrt(s) >= 0 inside
    const double c = 2.0 * rate * root;
    weight = root * root;
    const int b = layer[i];
    ax = -c * (vx - vel_x[b]);
    ay = -c * (vy - vel_y[b]);
    alpha = -c * w;
    const int s = target[i];
    if (s < 0) return true;
    double ex = x - (site_x[s] + shift_x[b]), ey = y - (site_y[s] + shift_y[b]);
    box.min_image(ex, ey);  // site and shift each within the box: under 1.5 box lengths
    const double k = rate * rate * weight;
    ax -= k * ex;
    ay -= k * ey;
    return true;
  }
};

}  // namespace grainlift::dem::detail
