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
  double phase = 0;       ///< pi / width (1/m)
  double rate = 0;        ///< 1/s
  const double* site_x = nullptr;
  const double* site_y = nullptr;
  /// per layer: where the sites have moved with the bed at the matching (m) and the layer's
  /// velocity (m/s; the drag acts on v - vel); since the matching, @p since s
  const double* off_x = nullptr;
  const double* off_y = nullptr;
  const double* vel_x = nullptr;
  const double* vel_y = nullptr;
  const std::int32_t* layer = nullptr;  ///< per grain
  double since = 0;
  const int* target = nullptr;  ///< per grain: its site or -1
  PeriodicBox box;

  /// The band's pull on grain @p i at (x, y) moving at (vx, vy, w), into (ax, ay, alpha);
  /// false (and nothing written) outside the band:
  /// with s = sin^2(pi xi), xi = (x - centre) / width + 1/2 in (0, 1), a = -s rate^2 (x -
  /// site - off - vel since) - 2 sqrt(s) rate (v - vel) with the grain's layer's off and vel
  /// (critically damped at every xi), alpha = -2 sqrt(s) rate w.
  /// @p weight: s, the ramp.
  inline bool pull(int i, double x, double y, double vx, double vy, double w, double& ax,
                   double& ay, double& alpha, double& weight) const {
    double dx = x - centre, dy0 = 0;
    box.min_image(dx, dy0);
    if (!(std::fabs(dx) < half)) return false;
    const double root = std::sin(phase * (dx + half));  // sqrt(s) >= 0 inside
    const double c = 2.0 * rate * root;
    weight = root * root;
    const int b = layer[i];
    ax = -c * (vx - vel_x[b]);
    ay = -c * (vy - vel_y[b]);
    alpha = -c * w;
    const int s = target[i];
    if (s < 0) return true;
    const double sx = site_x[s] + (off_x[b] + vel_x[b] * since);
    const double sy = site_y[s] + (off_y[b] + vel_y[b] * since);
    double ex = x - sx, ey = y - sy;
    box.min_image_any(ex, ey);  // the bed may have slid by several box lengths
    const double k = rate * rate * root * root;
    ax -= k * ex;
    ay -= k * ey;
    return true;
  }
};

}  // namespace grainlift::dem::detail
