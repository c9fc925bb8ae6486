// Coarse graining on the intruder-frame grid (Kumar 2019 appendix).
#include "grainlift/dem/measure/field_accumulator.h"

#include <string>

#include "grainlift/dem/errors.h"

#include <algorithm>
#include <cmath>

#include "step/pair_contacts.h"

namespace grainlift::dem {

FieldAccumulator::FieldAccumulator(const FieldGridSpec& spec) : spec_(spec) {
  const std::size_t n = static_cast<std::size_t>(std::max(0, spec.nx) * std::max(0, spec.ny));
  for (auto* v : {&gamma_, &gvx_, &gvy_, &gv2_, &sxx_, &sxy_, &syy_}) v->assign(n, 0.0);
}

void FieldAccumulator::add_stress(double mx, double my, double fx, double fy, double lx,
                                  double ly) {
  const double h = spec_.spacing;
  const int i = static_cast<int>(std::floor((mx - spec_.x0) / h));
  const int j = static_cast<int>(std::floor((my - spec_.y0) / h));
  if (i < 0 || j < 0 || i >= spec_.nx || j >= spec_.ny) return;
  const std::size_t b = static_cast<std::size_t>(j) * spec_.nx + i;
  const double inv_area = 1.0 / (h * h);
  sxx_[b] -= fx * lx * inv_area;
  syy_[b] -= fy * ly * inv_area;
  sxy_[b] -= 0.5 * (fx * ly + fy * lx) * inv_area;
}

void FieldAccumulator::add_snapshot(const DemSystem& s) {
  const auto& p = s.particles();
  const auto& in = s.intruder();
  const PeriodicBox& box = s.box();
  const double h = spec_.spacing;
  const double sub = 0.1 * h;
  const double gx1 = spec_.x0 + spec_.nx * h, gy1 = spec_.y0 + spec_.ny * h;
  for (int g = 0; g < s.grains(); ++g) {
    double cx = p.x[g] - in.x, cy = p.y[g] - in.y;  // disk centre in the intruder frame
    box.min_image(cx, cy);
    const double r = p.r[g];
    if (cx + r < spec_.x0 || cx - r > gx1 || cy + r < spec_.y0 || cy - r > gy1) continue;
    const int i0 = std::max(0, static_cast<int>(std::floor((cx - r - spec_.x0) / h)));
    const int i1 = std::min(spec_.nx - 1, static_cast<int>(std::floor((cx + r - spec_.x0) / h)));
    const int j0 = std::max(0, static_cast<int>(std::floor((cy - r - spec_.y0) / h)));
    const int j1 = std::min(spec_.ny - 1, static_cast<int>(std::floor((cy + r - spec_.y0) / h)));
    const double r2 = r * r;
    for (int j = j0; j <= j1; ++j) {
      const double by0 = spec_.y0 + j * h, by1 = by0 + h;
      for (int i = i0; i <= i1; ++i) {
        const double bx0 = spec_.x0 + i * h, bx1 = bx0 + h;
        // nearest and farthest points of the bin from the disk centre
        const double nx = std::clamp(cx, bx0, bx1) - cx, ny = std::clamp(cy, by0, by1) - cy;
        if (nx * nx + ny * ny >= r2) continue;
        const double fx = std::max(std::abs(bx0 - cx), std::abs(bx1 - cx));
        const double fy = std::max(std::abs(by0 - cy), std::abs(by1 - cy));
        double gamma;
        if (fx * fx + fy * fy <= r2) {
          gamma = h * h;
        } else {
          int inside = 0;
          for (int b = 0; b < 10; ++b) {
            const double sy = by0 + (b + 0.5) * sub - cy;
            for (int a = 0; a < 10; ++a) {
              const double sx = bx0 + (a + 0.5) * sub - cx;
              if (sx * sx + sy * sy < r2) ++inside;
            }
          }
          gamma = inside * sub * sub;
        }
        if (gamma <= 0) continue;
        const double rx = 0.5 * (bx0 + bx1) - cx, ry = 0.5 * (by0 + by1) - cy;
        const double vx = p.vx[g] - p.w[g] * ry - in.vx;  // eq. (A1)
        const double vy = p.vy[g] + p.w[g] * rx - in.vy;  // eq. (A2)
        const std::size_t bin = static_cast<std::size_t>(j) * spec_.nx + i;
        gamma_[bin] += gamma;
        gvx_[bin] += gamma * vx;
        gvy_[bin] += gamma * vy;
        gv2_[bin] += gamma * (vx * vx + vy * vy);
      }
    }
  }
  // contact stress: grain-grain and grain-wall pairs, then grain-intruder contacts
  detail::for_each_pair_contact(s, [&](double fx, double fy, double lx, double ly, double mx,
                                       double my) {
    double rx = mx - in.x, ry = my - in.y;  // the midpoint in the intruder frame
    box.min_image(rx, ry);
    add_stress(rx, ry, fx, fy, lx, ly);
  });
  const IntruderContacts& ic = s.intruder_contacts();
  for (std::size_t c = 0; c < ic.grain.size(); ++c) {
    if (!ic.touching[c]) continue;
    const int g = ic.grain[c];
    double lx = p.x[g] - in.x, ly = p.y[g] - in.y;
    box.min_image(lx, ly);
    add_stress(0.5 * lx, 0.5 * ly, ic.fx[c], ic.fy[c], lx, ly);
  }
  ++snapshots_;
}

FieldAverages FieldAccumulator::finish() const {
  FieldAverages f;
  f.nx = spec_.nx;
  f.ny = spec_.ny;
  f.snapshots = snapshots_;
  const std::size_t n = gamma_.size();
  for (auto* v : {&f.area_fraction, &f.vx, &f.vy, &f.granular_temperature, &f.sxx, &f.sxy,
                  &f.syy}) {
    v->assign(n, 0.0);
  }
  if (snapshots_ == 0) return f;
  const double h2 = spec_.spacing * spec_.spacing;
  for (std::size_t b = 0; b < n; ++b) {
    f.area_fraction[b] = gamma_[b] / (snapshots_ * h2);  // eq. (A6)
    if (gamma_[b] > 0) {
      const double vx = gvx_[b] / gamma_[b], vy = gvy_[b] / gamma_[b];  // eq. (A3)-(A4)
      f.vx[b] = vx;
      f.vy[b] = vy;
      // eq. (A7): 0.5 <|v* - <v*>|^2>, Gamma-weighted
      f.granular_temperature[b] = std::max(0.0, 0.5 * (gv2_[b] / gamma_[b] - vx * vx - vy * vy));
    }
    f.sxx[b] = sxx_[b] / snapshots_;
    f.sxy[b] = sxy_[b] / snapshots_;
    f.syy[b] = syy_[b] / snapshots_;
  }
  return f;
}

void FieldAccumulator::restore(const FieldSums& s) {
  for (const auto* v : {&s.gamma, &s.gvx, &s.gvy, &s.gv2, &s.sxx, &s.sxy, &s.syy}) {
    if (v->size() != gamma_.size()) {
      throw ConfigError("the checkpoint's field sums have " + std::to_string(v->size()) +
                        " bins, this grid " + std::to_string(gamma_.size()));
    }
  }
  snapshots_ = s.snapshots;
  gamma_ = s.gamma;
  gvx_ = s.gvx;
  gvy_ = s.gvy;
  gv2_ = s.gv2;
  sxx_ = s.sxx;
  sxy_ = s.sxy;
  syy_ = s.syy;
}

}  // namespace grainlift::dem
