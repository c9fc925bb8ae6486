// The co-moving window (DemSystem::set_window): a band across the box, half a box length
// from the intruder and moving with it, pulls the grains inside it back onto the sites of the
// prepared bed, so that the intruder, coming round the periodic box, meets that bed again
// instead of its own wake. No grain is added or removed: the area fraction is that of the
// prepared bed exactly.
//
// Sites, not each grain's own position: the prepared bed has a hole where the intruder
// started, and the grains that flowed into it after the intruder left would be pulled out of
// it again, opening a cavity the intruder meets one box length later. So the grains in reach
// of the band are matched afresh to the sites near them (closest pairs first, each site and
// grain used once, within match_radius): a grain in the old hole has no site near it and stays
// free, and the grains around it settle on the sites around the hole. The matching happens at
// fixed steps (a list build is forced there), not at every build: when the lists are built
// depends on history (a run resumed from a checkpoint, a woken sleeper), and the results must
// not.
//
// The bed may slide along the box: the sites move with each layer's median displacement and
// velocity outside the band, and each grain's pull is less its share of its layer's total, so
// that the band restores the arrangement of the grains without holding the bed back or driving
// it (docs/performance.md, Skips, measures what each of those did). The pull itself is in
// window_band.h, evaluated by window_forces() before each kick.
#include <algorithm>
#include <cmath>
#include <string>

#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/errors.h"
#include "boundaries/window_band.h"

namespace grainlift::dem {

void DemSystem::set_window(double width, double rate, double match_radius) {
  Window& w = window_;
  for (int g : w.flagged) grain_flags_[g] &= static_cast<std::uint8_t>(~kWindow);
  w = Window{};
  if (!(width > 0)) return;
  const PeriodicBox& box = opt_.box;
  if (!intruder_.present) throw ConfigError("the co-moving window needs the intruder");
  if (!box.periodic_x || intruder_.vy != 0.0 || intruder_.vx == 0.0) {
    throw ConfigError("the co-moving window needs a box periodic in x and an intruder moving "
                      "along x");
  }
  if (!(rate > 0) || !(match_radius > 0) || !(width < box.lx())) {
    throw ConfigError("the co-moving window needs rate > 0, match_radius > 0 and a band "
                      "narrower than the box");
  }
  w.width = width;
  w.rate = rate;
  w.match_radius = match_radius;
  w.vx = intruder_.vx;
  w.step0 = steps_;
  // the band moves a tenth of the match radius between two matchings
  w.match_every = std::max<std::int64_t>(
      1, std::llround(0.1 * match_radius / (std::fabs(w.vx) * opt_.dt)));
  w.next_match = steps_;
  double x0 = intruder_.x + 0.5 * box.lx(), y0 = 0;
  box.wrap(x0, y0);
  w.x0 = x0;
  w.site_x.assign(p_.x.begin(), p_.x.begin() + n_grains_);
  w.site_y.assign(p_.y.begin(), p_.y.begin() + n_grains_);
  index_window_sites();
  // the next build flags the band's grains
  primed_ = false;
}

void DemSystem::index_window_sites() {
  Window& w = window_;
  const PeriodicBox& box = opt_.box;
  const auto n = static_cast<std::size_t>(n_grains_);
  w.target.assign(n, -1);
  w.image_x.assign(n, 0);
  w.image_y.assign(n, 0);
  w.last_x.assign(p_.x.begin(), p_.x.begin() + n_grains_);
  w.last_y.assign(p_.y.begin(), p_.y.begin() + n_grains_);
  // layers two match radii (two grain diameters) high
  const int nl = std::max(1, static_cast<int>(box.ly() / (2.0 * w.match_radius)));
  w.bin_height = box.ly() / nl;
  for (auto* v : {&w.off_x, &w.off_y, &w.vel_x, &w.vel_y}) v->assign(static_cast<std::size_t>(nl), 0.0);
  w.layer.assign(n, 0);
  for (auto* v : {&w.acc_x, &w.acc_y, &w.acc_w}) v->assign(n, 0.0);
  w.weight.assign(n, 0.0);
  w.taken.assign(n, 0);
  // sites by bins along x, at least match_radius wide: a grain's candidates lie in its own
  // bin and the two beside it
  const int nb = std::max(1, static_cast<int>(box.lx() / w.match_radius));
  w.bin_width = box.lx() / nb;
  w.bin_first.assign(static_cast<std::size_t>(nb) + 1, 0);
  auto bin_of = [&](double x) {
    const int b = static_cast<int>((x - box.xmin) / w.bin_width);
    return std::min(nb - 1, std::max(0, b));
  };
  for (int s = 0; s < n_grains_; ++s) ++w.bin_first[static_cast<std::size_t>(bin_of(w.site_x[s])) + 1];
  for (int b = 0; b < nb; ++b) w.bin_first[b + 1] += w.bin_first[b];
  w.bin_site.assign(n, 0);
  std::vector<int> fill(w.bin_first.begin(), w.bin_first.end() - 1);
  for (int s = 0; s < n_grains_; ++s) w.bin_site[fill[bin_of(w.site_x[s])]++] = s;
}

void DemSystem::window_forces(std::int64_t kick_step) {
  Window& w = window_;
  detail::WindowBand band;
  band.centre = window_centre(kick_step);
  band.half = 0.5 * w.width;
  band.inv_half = 2.0 / w.width;
  band.rate = w.rate;
  band.site_x = w.site_x.data();
  band.site_y = w.site_y.data();
  band.target = w.target.data();
  band.box = opt_.box;
  // each layer's sites: moved by the slide at the matching and the layer's velocity since,
  // wrapped into the box (the bed may have slid by several box lengths)
  const double since = opt_.dt * static_cast<double>(kick_step - w.match_step);
  const std::size_t nlayers = w.off_x.size();
  w.shift_x.resize(nlayers);
  w.shift_y.resize(nlayers);
  for (std::size_t l = 0; l < nlayers; ++l) {
    double sx = w.off_x[l] + w.vel_x[l] * since, sy = w.off_y[l] + w.vel_y[l] * since;
    opt_.box.min_image_any(sx, sy);
    w.shift_x[l] = sx;
    w.shift_y[l] = sy;
  }
  band.shift_x = w.shift_x.data();
  band.shift_y = w.shift_y.data();
  band.vel_x = w.vel_x.data();
  band.vel_y = w.vel_y.data();
  band.layer = w.layer.data();
  // each grain's pull, and per layer the momentum it adds and the grains' weights (ramp x mass)
  const std::size_t nl = w.off_x.size();
  w.layer_sum.assign(3 * nl, 0.0);
  for (int g : w.flagged) {
    double ax = 0, ay = 0, al = 0, s = 0;
    const bool inside = band.pull(g, p_.x[g], p_.y[g], p_.vx[g], p_.vy[g], p_.w[g], ax, ay, al, s);
    w.weight[g] = inside ? s : 0.0;
    if (inside) {
      double* q = w.layer_sum.data() + 3 * w.layer[g];
      const double m = p_.mass[g];
      q[0] += m * s;
      q[1] += m * ax;
      q[2] += m * ay;
    }
    w.acc_x[g] = ax;
    w.acc_y[g] = ay;
    w.acc_w[g] = al;
  }
  // The recoil: the layer's momentum taken back from its band grains in proportion to their
  // ramp, so that the band pushes no layer as a whole (a band that did either held the bed
  // back or, following it, drove it: on the reduced Kumar bed three times the drag, or a bed
  // overtaking the intruder). Not in equal shares: a grain at the band's edge, with no spring
  // to hold it, would be driven by the others' recoil.
  // (per layer the pull per unit ramp, sum m a / sum m s, then each grain's share)
  for (std::size_t l = 0; l < nl; ++l) {
    double* q = w.layer_sum.data() + 3 * l;
    if (q[0] > 0) {
      q[1] /= q[0];
      q[2] /= q[0];
    }
  }
  for (int g : w.flagged) {
    if (!(w.weight[g] > 0)) continue;
    const double* q = w.layer_sum.data() + 3 * w.layer[g];
    w.acc_x[g] -= w.weight[g] * q[1];
    w.acc_y[g] -= w.weight[g] * q[2];
  }
}

double DemSystem::window_centre(std::int64_t step) const {
  double x = window_.x0 + window_.vx * opt_.dt * static_cast<double>(step - window_.step0), y = 0;
  opt_.box.wrap_any(x, y);  // many laps
  return x;
}

void DemSystem::update_window() {
  Window& w = window_;
  if (!(w.width > 0)) return;
  const PeriodicBox& box = opt_.box;
  for (int g : w.flagged) grain_flags_[g] &= static_cast<std::uint8_t>(~kWindow);
  w.flagged.clear();
  // Until the next build the band moves by less than the skin (the intruder's displacement
  // triggers a build) and a grain by less than half of it: every grain that can be inside the
  // band before then is flagged. And each grain's box lengths crossed since the last build (it
  // moves far less than half a box between builds): the counts, unlike sums of displacements,
  // do not depend on when builds happen.
  const double lx = box.lx(), ly = box.ly();
  const double centre = window_centre(steps_);
  const double reach = 0.5 * w.width + 2.0 * skin_;
  for (int g = 0; g < n_grains_; ++g) {
    const double jx = p_.x[g] - w.last_x[g], jy = p_.y[g] - w.last_y[g];
    if (box.periodic_x && jx < -0.5 * lx) ++w.image_x[g];
    if (box.periodic_x && jx > 0.5 * lx) --w.image_x[g];
    if (box.periodic_y && jy < -0.5 * ly) ++w.image_y[g];
    if (box.periodic_y && jy > 0.5 * ly) --w.image_y[g];
    w.last_x[g] = p_.x[g];
    w.last_y[g] = p_.y[g];
    double dx = p_.x[g] - centre, dy = 0;
    box.min_image(dx, dy);
    if (std::fabs(dx) < reach) {
      grain_flags_[g] |= kWindow;
      w.flagged.push_back(g);
    }
  }
  if (steps_ < w.next_match) return;  // the sites stay those of the last matching
  w.next_match = (steps_ / w.match_every + 1) * w.match_every;
  std::fill(w.target.begin(), w.target.end(), -1);
  // Where the sites are now: the bed may slide along the box, and sites held in place would
  // hold it back (on the reduced Kumar bed, three times the drag). Each layer's median
  // displacement (from each grain's own starting position) and median velocity over its grains
  // outside the band's reach: the band follows the bed. Not its own grains, which it moves: a
  // band that followed them carried them along at whatever speed they had (on the reduced
  // Kumar bed they ran away). Medians: the grains the intruder stirred, or that swapped places,
  // have large displacements from their own starting positions that say nothing about where
  // the bed has gone. A layer with no grain outside keeps its last values.
  {
    const int nl = static_cast<int>(w.off_x.size());
    w.layer_first.assign(static_cast<std::size_t>(nl) + 1, 0);
    for (int g = 0; g < n_grains_; ++g) {
      const int l = std::min(nl - 1, std::max(0, static_cast<int>((p_.y[g] - box.ymin) / w.bin_height)));
      w.layer[g] = l;
      if (!(grain_flags_[g] & kWindow)) ++w.layer_first[static_cast<std::size_t>(l) + 1];
    }
    for (int l = 0; l < nl; ++l) w.layer_first[l + 1] += w.layer_first[l];
    w.layer_grain.resize(static_cast<std::size_t>(w.layer_first[nl]));
    std::vector<int>& fill = w.layer_fill;
    fill.assign(w.layer_first.begin(), w.layer_first.end() - 1);
    for (int g = 0; g < n_grains_; ++g) {
      if (!(grain_flags_[g] & kWindow)) w.layer_grain[fill[w.layer[g]]++] = g;
    }
    auto median = [&](int l, auto value) {
      w.scratch.clear();
      for (int q = w.layer_first[l]; q < w.layer_first[l + 1]; ++q) w.scratch.push_back(value(w.layer_grain[q]));
      const auto mid = w.scratch.begin() + static_cast<std::ptrdiff_t>(w.scratch.size() / 2);
      std::nth_element(w.scratch.begin(), mid, w.scratch.end());
      return *mid;
    };
    for (int l = 0; l < nl; ++l) {
      if (w.layer_first[l + 1] == w.layer_first[l]) continue;
      w.off_x[l] = median(l, [&](int g) { return p_.x[g] + w.image_x[g] * lx - w.site_x[g]; });
      w.off_y[l] = median(l, [&](int g) { return p_.y[g] + w.image_y[g] * ly - w.site_y[g]; });
      w.vel_x[l] = median(l, [&](int g) { return p_.vx[g]; });
      w.vel_y[l] = median(l, [&](int g) { return p_.vy[g]; });
    }
    // inside advance() the positions have already drifted to the next step's (drifted_)
    w.match_step = drifted_ ? steps_ + 1 : steps_;
  }
  // candidate pairs (grain, site) within match_radius of the moved sites
  const double r2 = w.match_radius * w.match_radius;
  const int nb = static_cast<int>(w.bin_first.size()) - 1;
  w.candidates.clear();
  for (int g : w.flagged) {
    // the grain where it would be without the slide, among the sites where they were set
    const int l = w.layer[g];
    double gx = p_.x[g] - w.off_x[l], gy = p_.y[g] - w.off_y[l];
    box.wrap_any(gx, gy);
    const int b = std::min(nb - 1, std::max(0, static_cast<int>((gx - box.xmin) / w.bin_width)));
    for (int db = -1; db <= 1; ++db) {
      if (nb < 3 && db != 0) continue;
      const int bb = (b + db + nb) % nb;
      for (int q = w.bin_first[bb]; q < w.bin_first[bb + 1]; ++q) {
        const int s = w.bin_site[q];
        double ex = gx - w.site_x[s], ey = gy - w.site_y[s];
        box.min_image_any(ex, ey);
        const double d2 = ex * ex + ey * ey;
        if (d2 < r2) w.candidates.push_back({d2, g, s});
      }
    }
  }
  // closest pairs first (ties by grain, then site: the same matching on every run)
  std::sort(w.candidates.begin(), w.candidates.end(),
            [](const Window::Candidate& a, const Window::Candidate& b) {
              if (a.d2 != b.d2) return a.d2 < b.d2;
              if (a.grain != b.grain) return a.grain < b.grain;
              return a.site < b.site;
            });
  for (const Window::Candidate& c : w.candidates) {
    if (w.target[c.grain] >= 0 || w.taken[c.site]) continue;
    w.target[c.grain] = c.site;
    w.taken[c.site] = 1;
  }
  for (const Window::Candidate& c : w.candidates) w.taken[c.site] = 0;
  // how well the band restores the bed: the matched grains in its middle half
  double core2 = 0;
  int core = 0, inside = 0, inside_matched = 0;
  for (int g : w.flagged) {
    double dx = p_.x[g] - centre, dy = 0;
    box.min_image(dx, dy);
    if (std::fabs(dx) >= 0.5 * w.width) continue;
    ++inside;
    const int s = w.target[g];
    if (s < 0) continue;
    ++inside_matched;
    if (std::fabs(dx) < 0.25 * w.width) {
      const int l = w.layer[g];
      double ex = p_.x[g] - (w.site_x[s] + w.off_x[l]), ey = p_.y[g] - (w.site_y[s] + w.off_y[l]);
      box.min_image_any(ex, ey);
      core2 += ex * ex + ey * ey;
      ++core;
    }
  }
  ++w.sums.builds;
  w.sums.band_grains += inside;
  w.sums.matched_fraction += inside > 0 ? double(inside_matched) / inside : 1.0;
  w.sums.core_rms += core > 0 ? std::sqrt(core2 / core) : 0.0;
}

double DemSystem::window_band_contacts() const {
  if (!(window_.width > 0)) return 0.0;
  const PeriodicBox& box = opt_.box;
  const double centre = window_centre(steps_);
  auto in_band = [&](int g) {
    if (g >= n_grains_) return false;
    double dx = p_.x[g] - centre, dy = 0;
    box.min_image(dx, dy);
    return std::fabs(dx) < 0.5 * window_.width;
  };
  long long band = 0, ends = 0;
  for (int g = 0; g < n_grains_; ++g) band += in_band(g);
  const std::size_t np = nl_.pairs();
  for (std::size_t k = 0; k < np; ++k) {
    const int i = nl_.owner[k], j = nl_.partner[k];
    const bool bi = in_band(i), bj = in_band(j);
    if (!bi && !bj) continue;
    double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j];
    box.min_image(dx, dy);
    const double rs = p_.r[i] + p_.r[j];
    if (dx * dx + dy * dy < rs * rs) ends += int(bi) + int(bj);
  }
  return band > 0 ? double(ends) / double(band) : 0.0;
}

DemSystem::WindowStats DemSystem::window_stats() const {
  WindowStats s = window_.sums;
  for (double o : window_.off_x) s.slide += o / static_cast<double>(window_.off_x.size());
  if (s.builds > 0) {
    s.band_grains /= double(s.builds);
    s.matched_fraction /= double(s.builds);
    s.core_rms /= double(s.builds);
  }
  return s;
}

}  // namespace grainlift::dem
