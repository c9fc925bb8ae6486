// The bed's stress away from the intruder (far_field_stress.h).
#include "grainlift/dem/measure/far_field_stress.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "grainlift/dem/system/dem_system.h"
#include "step/pair_contacts.h"

namespace grainlift::dem {

namespace {

/// The region around the intruder in the current state: x range (periodic or between side
/// walls), y range of the strip clipped at the walls.
struct Strip {
  double x0, x1, y0, y1;
  bool periodic_x;
};

Strip strip_of(const DemSystem& s, const DemConfig& c, const FarFieldRegion& r) {
  const double d = c.grain_diameter;
  const double yi = s.intruder().y;
  const double y_bottom = c.wall_bottom ? c.ymin + 0.5 * d : -std::numeric_limits<double>::max();
  double y_top = c.wall_top ? c.ymax - 0.5 * d : std::numeric_limits<double>::max();
  if (s.lid()) y_top = s.lid()->state().y;
  Strip st;
  st.periodic_x = c.periodic_x;
  st.x0 = c.xmin + (c.wall_left ? 0.5 * d + r.wall_margin : 0.0);
  st.x1 = c.xmax - (c.wall_right ? 0.5 * d + r.wall_margin : 0.0);
  st.y0 = std::max(yi - r.half_height, y_bottom + r.wall_margin);
  st.y1 = std::min(yi + r.half_height, y_top - r.wall_margin);
  return st;
}

/// Area of the strip minus the exclusion disk (radius re around (xi, yi)), by the chord
/// lengths of the disk inside the strip on 2,000 rows (relative error below 1e-5).
double region_area(const Strip& st, double xi, double yi, double re, double width) {
  if (!(st.y1 > st.y0) || !(st.x1 > st.x0)) return 0;
  const double a = std::max(st.y0, yi - re), b = std::min(st.y1, yi + re);
  double disk = 0;
  if (b > a) {
    constexpr int kRows = 2000;
    const double dy = (b - a) / kRows;
    for (int k = 0; k < kRows; ++k) {
      const double y = a + (k + 0.5) * dy - yi;
      const double half = std::sqrt(std::max(0.0, re * re - y * y));
      double chord;
      if (st.periodic_x) {
        chord = std::min(2 * half, width);
      } else {
        chord = std::max(0.0, std::min(xi + half, st.x1) - std::max(xi - half, st.x0));
      }
      disk += chord * dy;
    }
  }
  return (st.x1 - st.x0) * (st.y1 - st.y0) - disk;
}

}  // namespace

FarFieldRegion FarFieldRegion::of(const DemConfig& c) {
  FarFieldRegion r;
  r.exclusion = 3.0 * c.intruder_diameter;
  r.half_height = 1.5 * c.intruder_diameter;
  r.wall_margin = 2.0 * c.grain_diameter;
  return r;
}

FarFieldSample far_field_stress(const DemSystem& s, const DemConfig& c,
                                const FarFieldRegion& region) {
  const auto& p = s.particles();
  const auto& in = s.intruder();
  const PeriodicBox& box = s.box();
  const Strip st = strip_of(s, c, region);
  const double re2 = region.exclusion * region.exclusion;
  // a point (lab frame, wrapped) inside the region
  const auto inside = [&](double x, double y) {
    if (y < st.y0 || y >= st.y1) return false;
    if (!st.periodic_x && (x < st.x0 || x >= st.x1)) return false;
    if (!in.present) return true;
    double dx = x - in.x, dy = y - in.y;
    box.min_image(dx, dy);
    return dx * dx + dy * dy >= re2;
  };
  FarFieldSample out;
  out.time = s.time();
  out.area = region_area(st, in.x, in.y, in.present ? region.exclusion : 0.0, c.xmax - c.xmin);
  if (!(out.area > 0)) {
    out.pressure = out.sxx = out.sxy = out.syy = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  double wxx = 0, wxy = 0, wyy = 0;  // sum of f (x) l, symmetrised
  detail::for_each_pair_contact(s, [&](double fx, double fy, double lx, double ly, double mx,
                                       double my) {
    box.wrap(mx, my);
    if (!inside(mx, my)) return;
    wxx += fx * lx;
    wyy += fy * ly;
    wxy += 0.5 * (fx * ly + fy * lx);
  });
  // kinetic part: velocity fluctuations about the region's mean (mass-weighted)
  double m_sum = 0, mvx = 0, mvy = 0;
  for (int g = 0; g < s.grains(); ++g) {
    if (!inside(p.x[g], p.y[g])) continue;
    m_sum += p.mass[g];
    mvx += p.mass[g] * p.vx[g];
    mvy += p.mass[g] * p.vy[g];
  }
  if (m_sum > 0) {
    const double ux = mvx / m_sum, uy = mvy / m_sum;
    for (int g = 0; g < s.grains(); ++g) {
      if (!inside(p.x[g], p.y[g])) continue;
      const double vx = p.vx[g] - ux, vy = p.vy[g] - uy;
      wxx += p.mass[g] * vx * vx;
      wyy += p.mass[g] * vy * vy;
      wxy += p.mass[g] * vx * vy;
    }
  }
  out.sxx = -wxx / out.area;
  out.syy = -wyy / out.area;
  out.sxy = -wxy / out.area;
  out.pressure = -0.5 * (out.sxx + out.syy);
  return out;
}

}  // namespace grainlift::dem
