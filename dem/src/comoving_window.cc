// The co-moving window (DemSystem::set_window): a band across the box, half a box length
// from the intruder and moving with it, pulls the grains inside it back onto the sites of the
// prepared bed, so that the intruder, coming round the periodic box, meets that bed again
// instead of its own wake. The sites move with the band's grains when the bed slides along the
// box as a whole: the band restores the bed's structure, it does not hold the bed in place. No grain is added or removed: the area fraction is that of the
// prepared bed exactly.
//
// Sites, not each grain's own position: the prepared bed has a hole where the intruder
// started, and the grains that flowed into it after the intruder left would be pulled out of
// it again, opening a cavity the intruder meets one box length later. So at every list build
// the grains in reach of the band are matched afresh to the sites near them (closest pairs
// first, each site and grain used once, within match_radius): a grain in the old hole has no
// site near it and stays free, and the grains around it settle on the sites around the hole.
// The matching happens at fixed steps (a list build is forced there), not at every build: when
// the lists are built depends on history (a run resumed from a checkpoint, a woken sleeper),
// and the results must not. The pull itself (window_band.h) is evaluated by the kick.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "grainlift/dem/dem_system.h"
#include "grainlift/dem/errors.h"

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

double DemSystem::window_centre(std::int64_t step) const {
  double x = window_.x0 + window_.vx * opt_.dt * static_cast<double>(step - window_.step0), y = 0;
  // positions stay within a box length or two of it between wraps; several laps: modulo
  const PeriodicBox& box = opt_.box;
  x = box.xmin + std::fmod(x - box.xmin, box.lx());
  if (x < box.xmin) x += box.lx();
  box.wrap(x, y);
  return x;
}

void DemSystem::update_window() {
  Window& w = window_;
  if (!(w.width > 0)) return;
  const PeriodicBox& box = opt_.box;
  // box lengths crossed since the last build (a grain moves far less than half a box between
  // builds): the counts, unlike sums of displacements, do not depend on when builds happen
  const double lx = box.lx(), ly = box.ly();
  for (int g = 0; g < n_grains_; ++g) {
    const double jx = p_.x[g] - w.last_x[g], jy = p_.y[g] - w.last_y[g];
    if (box.periodic_x && jx < -0.5 * lx) ++w.image_x[g];
    if (box.periodic_x && jx > 0.5 * lx) --w.image_x[g];
    if (box.periodic_y && jy < -0.5 * ly) ++w.image_y[g];
    if (box.periodic_y && jy > 0.5 * ly) --w.image_y[g];
    w.last_x[g] = p_.x[g];
    w.last_y[g] = p_.y[g];
  }
  for (int g : w.flagged) grain_flags_[g] &= static_cast<std::uint8_t>(~kWindow);
  w.flagged.clear();
  // Until the next build the band moves by less than the skin (the intruder's displacement
  // triggers a build) and a grain by less than half of it: every grain that can be inside the
  // band before then is flagged.
  const double centre = window_centre(steps_);
  const double reach = 0.5 * w.width + 2.0 * skin_;
  for (int g = 0; g < n_grains_; ++g) {
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
  // Where the sites are now: the bed may slide along the box as a whole, and sites held in
  // place would hold it back (on the reduced Kumar bed, three times the drag). The median
  // displacement (from each grain's own starting position) and the median velocity of the
  // grains in the band's middle half: medians, so that the grains the intruder stirred, or
  // that wandered into its old hole, do not move the sites.
  {
    auto median = [&](auto value) {
      w.scratch.clear();
      for (int g : w.flagged) {
        double dx = p_.x[g] - centre, dy = 0;
        box.min_image(dx, dy);
        if (std::fabs(dx) < 0.25 * w.width) w.scratch.push_back(value(g));
      }
      if (w.scratch.empty()) return 0.0;
      const auto mid = w.scratch.begin() + static_cast<std::ptrdiff_t>(w.scratch.size() / 2);
      std::nth_element(w.scratch.begin(), mid, w.scratch.end());
      return *mid;
    };
    w.off_x = median([&](int g) { return p_.x[g] + w.image_x[g] * lx - w.site_x[g]; });
    w.off_y = median([&](int g) { return p_.y[g] + w.image_y[g] * ly - w.site_y[g]; });
    w.vel_x = median([&](int g) { return p_.vx[g]; });
    w.vel_y = median([&](int g) { return p_.vy[g]; });
    // inside advance() the positions have already drifted to the next step's (drifted_)
    w.match_step = drifted_ ? steps_ + 1 : steps_;
  }
  // candidate pairs (grain, site) within match_radius of the moved sites
  const double r2 = w.match_radius * w.match_radius;
  const int nb = static_cast<int>(w.bin_first.size()) - 1;
  w.candidates.clear();
  for (int g : w.flagged) {
    // the grain where it would be without the slide, among the sites where they were set
    double gx = p_.x[g] - w.off_x, gy = p_.y[g] - w.off_y;
    gx = box.xmin + std::fmod(gx - box.xmin, lx);
    if (gx < box.xmin) gx += lx;
    const int b = std::min(nb - 1, std::max(0, static_cast<int>((gx - box.xmin) / w.bin_width)));
    for (int db = -1; db <= 1; ++db) {
      if (nb < 3 && db != 0) continue;
      const int bb = (b + db + nb) % nb;
      for (int q = w.bin_first[bb]; q < w.bin_first[bb + 1]; ++q) {
        const int s = w.bin_site[q];
        double ex = gx - w.site_x[s], ey = gy - w.site_y[s];
        box.min_image(ex, ey);
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
      double ex = p_.x[g] - (w.site_x[s] + w.off_x), ey = p_.y[g] - (w.site_y[s] + w.off_y);
      box.min_image(ex, ey);
      core2 += ex * ex + ey * ey;
      ++core;
    }
  }
  ++w.sums.builds;
  w.sums.band_grains += inside;
  w.sums.matched_fraction += inside > 0 ? double(inside_matched) / inside : 1.0;
  w.sums.core_rms += core > 0 ? std::sqrt(core2 / core) : 0.0;
}

DemSystem::WindowStats DemSystem::window_stats() const {
  WindowStats s = window_.sums;
  if (s.builds > 0) {
    s.band_grains /= double(s.builds);
    s.matched_fraction /= double(s.builds);
    s.core_rms /= double(s.builds);
  }
  return s;
}

}  // namespace grainlift::dem
