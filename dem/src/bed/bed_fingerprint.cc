// Bed fingerprint (bed_fingerprint.h): contacts, rattlers, nearest gaps, fabric, area-fraction
// profiles of a bed at rest.
#include "grainlift/dem/bed/bed_fingerprint.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "grainlift/dem/system/system_setup.h"

namespace grainlift::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Positions and radii of every disk that can touch a grain: the grains first, then walls.
struct Bodies {
  std::vector<double> x, y, r;
  std::size_t grains = 0;
};

/// Calls f(i, j, dx, dy, dist) for every pair i < j (i a grain) whose centres are closer than
/// r_i + r_j + reach, with (dx, dy) = x_i - x_j by minimum image: a uniform cell grid.
template <class F>
void for_each_near_pair(const PeriodicBox& box, const Bodies& b, double reach, F&& f) {
  const double rmax = *std::max_element(b.r.begin(), b.r.end());
  const double cut = 2 * rmax + reach;
  const int nx = std::max(1, static_cast<int>(box.lx() / cut));
  const int ny = std::max(1, static_cast<int>(box.ly() / cut));
  std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(nx) * ny);
  auto cell_of = [&](double x, double y, int& cx, int& cy) {
    cx = std::clamp(static_cast<int>((x - box.xmin) / box.lx() * nx), 0, nx - 1);
    cy = std::clamp(static_cast<int>((y - box.ymin) / box.ly() * ny), 0, ny - 1);
  };
  for (std::size_t k = 0; k < b.x.size(); ++k) {
    int cx, cy;
    cell_of(b.x[k], b.y[k], cx, cy);
    cells[static_cast<std::size_t>(cy) * nx + cx].push_back(k);
  }
  for (std::size_t i = 0; i < b.grains; ++i) {
    int cx, cy;
    cell_of(b.x[i], b.y[i], cx, cy);
    // each neighbouring cell once, even when the grid is narrower than three cells
    std::vector<std::size_t> seen;
    for (int oy = -1; oy <= 1; ++oy) {
      for (int ox = -1; ox <= 1; ++ox) {
        int qx = cx + ox, qy = cy + oy;
        if (box.periodic_x) qx = (qx + nx) % nx;
        if (box.periodic_y) qy = (qy + ny) % ny;
        if (qx < 0 || qx >= nx || qy < 0 || qy >= ny) continue;
        const std::size_t q = static_cast<std::size_t>(qy) * nx + qx;
        if (std::find(seen.begin(), seen.end(), q) != seen.end()) continue;
        seen.push_back(q);
        for (std::size_t j : cells[q]) {
          if (j < b.grains && j <= i) continue;  // grain pairs once; walls from their grain
          double dx = b.x[i] - b.x[j], dy = b.y[i] - b.y[j];
          box.min_image(dx, dy);
          const double dist = std::hypot(dx, dy);
          if (dist < b.r[i] + b.r[j] + reach) f(i, j, dx, dy, dist);
        }
      }
    }
  }
}

/// Contacts per grain, rattlers, fabric and the histogram of each grain's nearest gap (to a
/// grain or a wall disk) into @p fp.
void contact_statistics(const DemConfig& c, const PackedBed& bed, const std::vector<Disk>& walls,
                        const PeriodicBox& box, BedFingerprint& fp) {
  const std::size_t n = bed.r.size();
  const double d = c.grain_diameter;
  Bodies b;
  b.x = bed.x;
  b.y = bed.y;
  b.r = bed.r;
  b.grains = n;
  for (const Disk& w : walls) {
    b.x.push_back(w.x);
    b.y.push_back(w.y);
    b.r.push_back(w.r);
  }
  fp.gap_edges = {-0.05, 0.0, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0};
  const double reach = fp.gap_edges.back() * d;
  std::vector<int> contacts(n, 0);
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  double fxx = 0, fxy = 0, fyy = 0;
  long long grain_contacts = 0;
  for_each_near_pair(box, b, reach, [&](std::size_t i, std::size_t j, double dx, double dy,
                                        double dist) {
    const double gap = dist - b.r[i] - b.r[j];
    nearest[i] = std::min(nearest[i], gap);
    if (j < n) nearest[j] = std::min(nearest[j], gap);
    if (gap >= 0) return;
    ++contacts[i];
    if (j >= n) return;
    ++contacts[j];
    const double nx = dx / dist, ny = dy / dist;
    fxx += nx * nx;
    fxy += nx * ny;
    fyy += ny * ny;
    ++grain_contacts;
  });
  long long total = 0, rattlers = 0;
  for (int k : contacts) {
    total += k;
    rattlers += k < 2 ? 1 : 0;
  }
  fp.contacts_per_grain = static_cast<double>(total) / static_cast<double>(n);
  fp.rattler_fraction = static_cast<double>(rattlers) / static_cast<double>(n);
  if (grain_contacts > 0) {
    fp.fabric_xx = fxx / static_cast<double>(grain_contacts);
    fp.fabric_xy = fxy / static_cast<double>(grain_contacts);
    fp.fabric_yy = fyy / static_cast<double>(grain_contacts);
  }
  const std::size_t bins = fp.gap_edges.size() - 1;
  fp.gap_fraction.assign(bins, 0.0);
  double gap_sum = 0;
  for (double g : nearest) {
    const double h = std::isfinite(g) ? g / d : fp.gap_edges.back();
    gap_sum += h;
    std::size_t k = 0;
    while (k + 1 < bins && h >= fp.gap_edges[k + 1]) ++k;
    fp.gap_fraction[k] += 1.0 / static_cast<double>(n);
  }
  fp.mean_gap = gap_sum / static_cast<double>(n);

}

/// Area-fraction profiles into @p fp: grain area by centre over the area open to grains
/// (inside the grains' region, outside the intruder, counted on a grid of points), in bands of
/// one grain diameter across y and in rings round the intruder.
void area_fraction_profiles(const DemConfig& c, const PackedBed& bed, const PeriodicBox& box,
                            BedFingerprint& fp) {
  const std::size_t n = bed.r.size();
  const double d = c.grain_diameter;
  const double y0 = c.ymin + (c.wall_bottom ? d : 0.0), y1 = c.ymax - (c.wall_top ? d : 0.0);
  const double x0 = c.xmin + (c.wall_left ? d : 0.0), x1 = c.xmax - (c.wall_right ? d : 0.0);
  const double ix = c.intruder_position[0], iy = c.intruder_position[1];
  const double R = 0.5 * c.intruder_diameter;
  auto open = [&](double x, double y) {
    double dx = x - ix, dy = y - iy;
    box.min_image(dx, dy);
    return x >= x0 && x <= x1 && y >= y0 && y <= y1 && dx * dx + dy * dy >= R * R;
  };
  const int bands = std::max(1, static_cast<int>((y1 - y0) / d + 1e-9));
  const double bh = (y1 - y0) / bands;
  std::vector<double> band_grain(static_cast<std::size_t>(bands), 0.0);
  const int rings = 10;
  std::vector<double> ring_grain(rings, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const double a = kPi * bed.r[k] * bed.r[k];
    const int j = static_cast<int>((bed.y[k] - y0) / bh);
    if (j >= 0 && j < bands) band_grain[static_cast<std::size_t>(j)] += a;
    double dx = bed.x[k] - ix, dy = bed.y[k] - iy;
    box.min_image(dx, dy);
    const int q = static_cast<int>((std::hypot(dx, dy) - R) / d);
    if (R > 0 && q >= 0 && q < rings) ring_grain[static_cast<std::size_t>(q)] += a;
  }
  constexpr int kSub = 400;  // grid points across the box width per band row, and per ring turn
  for (int j = 0; j < bands; ++j) {
    double open_area = 0;
    const int rows = 8;
    for (int s = 0; s < rows; ++s)
      for (int t = 0; t < kSub; ++t)
        open_area += open(x0 + (t + 0.5) * (x1 - x0) / kSub, y0 + (j + (s + 0.5) / rows) * bh)
                         ? 1.0 : 0.0;
    open_area *= (x1 - x0) * bh / (rows * kSub);
    fp.band_y.push_back(y0 + (j + 0.5) * bh);
    fp.band_area_fraction.push_back(
        open_area > 0 ? band_grain[static_cast<std::size_t>(j)] / open_area : 0.0);
  }
  if (R > 0) {
    for (int q = 0; q < rings; ++q) {
      const double ra = R + q * d;
      double open_area = 0;
      const int radial = 8;
      for (int s = 0; s < radial; ++s) {
        const double rr = ra + (s + 0.5) * d / radial;
        int inside = 0;
        for (int t = 0; t < kSub; ++t) {
          const double th = 2 * kPi * (t + 0.5) / kSub;
          double px = ix + rr * std::cos(th), py = iy + rr * std::sin(th);
          box.wrap(px, py);
          inside += open(px, py) ? 1 : 0;
        }
        open_area += 2 * kPi * rr * (d / radial) * inside / kSub;
      }
      fp.ring_r.push_back(ra + 0.5 * d);
      fp.ring_area_fraction.push_back(
          open_area > 0 ? ring_grain[static_cast<std::size_t>(q)] / open_area : 0.0);
    }
  }
}

}  // namespace

BedFingerprint bed_fingerprint(const DemConfig& c, const PackedBed& bed,
                               const std::vector<Disk>& walls) {
  BedFingerprint fp;
  if (bed.r.empty()) return fp;
  const PeriodicBox box = box_of(c);
  contact_statistics(c, bed, walls, box, fp);
  area_fraction_profiles(c, bed, box, fp);
  return fp;
}

}  // namespace grainlift::dem
