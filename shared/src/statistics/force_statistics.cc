#include "grainlift/shared/statistics/force_statistics.h"

#include <cmath>
#include <stdexcept>

namespace grainlift {

DragLift project_drag_lift(double fx, double fy, double vx, double vy) {
  const double v = std::hypot(vx, vy);
  if (!(v > 0)) throw std::invalid_argument("project_drag_lift: zero velocity");
  const double ex = vx / v, ey = vy / v;
  // z x e = (-ey, ex)
  return {-(fx * ex + fy * ey), fx * (-ey) + fy * ex};
}

}  // namespace grainlift
