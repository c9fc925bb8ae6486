// The simulation box: bounds, periodicity, minimum image and wrapping (lab frame, m).
#pragma once

#include <cmath>

namespace grainlift::dem {

struct PeriodicBox {
  double xmin = 0, xmax = 1, ymin = 0, ymax = 1;
  bool periodic_x = true, periodic_y = false;

  double lx() const { return xmax - xmin; }
  double ly() const { return ymax - ymin; }

  /// @brief Replace (dx, dy) by its minimum image in the periodic directions.
  /// Valid for |dx| < 1.5 lx (positions wrapped into the box).
  inline void min_image(double& dx, double& dy) const {
    if (periodic_x) {
      const double l = lx();
      if (dx > 0.5 * l) dx -= l;
      else if (dx < -0.5 * l) dx += l;
    }
    if (periodic_y) {
      const double l = ly();
      if (dy > 0.5 * l) dy -= l;
      else if (dy < -0.5 * l) dy += l;
    }
  }

  /// @brief The minimum image of a separation of any size (min_image: under 1.5 box lengths).
  inline void min_image_any(double& dx, double& dy) const {
    if (periodic_x) dx -= lx() * std::nearbyint(dx / lx());
    if (periodic_y) dy -= ly() * std::nearbyint(dy / ly());
  }

  /// @brief Wrap a position any number of box lengths away back into the box (wrap: under one).
  inline void wrap_any(double& x, double& y) const {
    if (periodic_x) {
      x = xmin + std::fmod(x - xmin, lx());  // exact
      if (x < xmin) x += lx();
    }
    if (periodic_y) {
      y = ymin + std::fmod(y - ymin, ly());
      if (y < ymin) y += ly();
    }
    wrap(x, y);  // xmin + a remainder just below the length may round to xmax
  }

  /// @brief Wrap a position back into the box in the periodic directions.
  inline void wrap(double& x, double& y) const {
    if (periodic_x) {
      if (x >= xmax) x -= lx();
      else if (x < xmin) x += lx();
    }
    if (periodic_y) {
      if (y >= ymax) y -= ly();
      else if (y < ymin) y += ly();
    }
  }
};

}  // namespace grainlift::dem
