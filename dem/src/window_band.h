// The co-moving window's pull on one grain (DemSystem::set_window): the acceleration that a
// band across the box adds to the grains inside it, a spring to each grain's site and a drag,
// both ramped from zero at the band's edges. Evaluated by the kick (velocity_verlet.cc) for
// the grains update_window() flagged; the bookkeeping is in comoving_window.cc.
#pragma once

#include <cmath>

#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem::detail {

struct WindowBand {
  double centre = 0;      ///< m, x of the band's middle
  double half = 0;        ///< m, half its width
  double phase = 0;       ///< pi / width (1/m)
  double rate = 0;        ///< 1/s
  const double* site_x = nullptr;
  const double* site_y = nullptr;
  double shift_x = 0, shift_y = 0;  ///< m, where the sites have moved with the bed
  double vel_x = 0, vel_y = 0;      ///< m/s, the band's velocity (the drag acts on v - vel)
  const int* target = nullptr;  ///< per grain: its site or -1
  PeriodicBox box;

  /// Adds to (ax, ay, alpha) the band's pull on grain @p i at (x, y) moving at (vx, vy, w):
  /// with s = sin^2(pi xi), xi = (x - centre) / width + 1/2 in (0, 1), a = -s rate^2 (x -
  /// site - shift) - 2 sqrt(s) rate (v - vel) (critically damped at every xi), alpha = -2
  /// sqrt(s) rate w;
  /// nothing outside the band (the same bits as an unflagged grain).
  inline void add(int i, double x, double y, double vx, double vy, double w, double& ax,
                  double& ay, double& alpha) const {
    double dx = x - centre, dy0 = 0;
    box.min_image(dx, dy0);
    if (!(std::fabs(dx) < half)) return;
    const double root = std::sin(phase * (dx + half));  // sqrt(s) >= 0 inside
    const double c = 2.0 * rate * root;
    ax -= c * (vx - vel_x);
    ay -= c * (vy - vel_y);
    alpha -= c * w;
    const int s = target[i];
    if (s < 0) return;
    double ex = x - (site_x[s] + shift_x), ey = y - (site_y[s] + shift_y);
    box.min_image(ex, ey);
    const double k = rate * rate * root * root;
    ax -= k * ex;
    ay -= k * ey;
  }
};

}  // namespace grainlift::dem::detail
