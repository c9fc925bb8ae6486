// DemSystem::snapshot and restore: the state between two advance() calls, for checkpoints
// (checkpoint.h). The state between calls is that of single steps (dem_system.cc): positions,
// velocities and accelerations at t, the springs of the pairs that touched at the last step,
// the intruder and the lid. The lists are rebuilt on restore: when the lists are built does
// not change a bit of the results (every per-grain sum is over the touching pairs in pair
// order, and a touching pair's spring survives any rebuild).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include "grainlift/dem/system/checkpoint.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/errors.h"

namespace grainlift::dem {

namespace {
/// Whether @p v is not +0.0 (a spring of -0.0 is kept too: its bits are state).
bool nonzero_bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b != 0;
}
}  // namespace

SystemSnapshot DemSystem::snapshot() const {
  SystemSnapshot s;
  s.grains.resize(static_cast<std::size_t>(n_grains_));
  s.frozen.resize(static_cast<std::size_t>(n_total_ - n_grains_));
  for (int i = 0; i < n_total_; ++i) {
    Disk& d = i < n_grains_ ? s.grains[i] : s.frozen[i - n_grains_];
    d.x = p_.x[i];
    d.y = p_.y[i];
    d.r = p_.r[i];
    d.mass = p_.mass[i];
    d.vx = p_.vx[i];
    d.vy = p_.vy[i];
    d.w = p_.w[i];
  }
  s.ax.assign(p_.ax.begin(), p_.ax.begin() + n_grains_);
  s.ay.assign(p_.ay.begin(), p_.ay.begin() + n_grains_);
  s.alpha.assign(p_.alpha.begin(), p_.alpha.begin() + n_grains_);
  s.time = time_;
  s.steps = steps_;
  s.intruder = intruder_;
  for (int i = 0; i < n_grains_; ++i) {
    for (std::int64_t k = nl_.first[i]; k < nl_.first[i + 1]; ++k) {
      if (!nonzero_bits(nl_.sx[k]) && !nonzero_bits(nl_.sy[k])) continue;
      s.pair_i.push_back(i);
      s.pair_j.push_back(nl_.partner[k]);
      s.pair_sx.push_back(nl_.sx[k]);
      s.pair_sy.push_back(nl_.sy[k]);
    }
  }
  for (std::size_t b = 0; b < ic_.grain.size(); ++b) {
    if (!nonzero_bits(ic_.sx[b]) && !nonzero_bits(ic_.sy[b])) continue;
    s.ic_grain.push_back(ic_.grain[b]);
    s.ic_sx.push_back(ic_.sx[b]);
    s.ic_sy.push_back(ic_.sy[b]);
  }
  if (lid_) {
    s.has_lid = true;
    s.lid = lid_->state();
    s.lid_disk_y = lid_->disk_y();
    s.lid_disk_velocity = lid_->disk_velocity();
  }
  s.max_overlap = max_overlap_;
  s.builds = builds_;
  s.steps_on_one = steps_on_one_;
  s.steps_on_team = steps_on_team_;
  s.sleep_grain_steps = sleep_grain_steps_;
  s.wake_builds = wake_builds_;
  s.woken = woken_;
  return s;
}

void DemSystem::restore(const SystemSnapshot& s) {
  if (s.has_lid != lid_.has_value()) {
    throw ConfigError(std::string("the checkpoint was taken ") + (s.has_lid ? "with" : "without") +
                      " a pressure lid, this system has " + (lid_ ? "one" : "none"));
  }
  set_bodies(s.grains, s.frozen);
  for (std::size_t j = 0; j < s.frozen.size(); ++j) {
    // frozen disks carry their velocity into the contact law (the lid's)
    p_.vx[n_grains_ + j] = s.frozen[j].vx;
    p_.vy[n_grains_ + j] = s.frozen[j].vy;
  }
  std::copy(s.ax.begin(), s.ax.end(), p_.ax.begin());
  std::copy(s.ay.begin(), s.ay.end(), p_.ay.begin());
  std::copy(s.alpha.begin(), s.alpha.end(), p_.alpha.begin());
  time_ = s.time;
  steps_ = s.steps;
  intruder_ = s.intruder;
  if (lid_) lid_->restore(s.lid, s.lid_disk_y, s.lid_disk_velocity);
  build_lists();
  for (std::size_t k = 0; k < s.pair_i.size(); ++k) {
    const int i = s.pair_i[k], j = s.pair_j[k];
    const auto b = nl_.partner.begin() + nl_.first[i], e = nl_.partner.begin() + nl_.first[i + 1];
    const auto at = std::lower_bound(b, e, j);
    if (at == e || *at != j) {
      throw ConfigError("the checkpoint's spring of pair (" + std::to_string(i) + ", " +
                        std::to_string(j) + ") has no pair in the rebuilt list: not this bed");
    }
    const auto kk = at - nl_.partner.begin();
    nl_.sx[kk] = s.pair_sx[k];
    nl_.sy[kk] = s.pair_sy[k];
  }
  for (std::size_t b = 0; b < s.ic_grain.size(); ++b) {
    const int slot = ic_slot_[s.ic_grain[b]];
    if (slot < 0) {
      throw ConfigError("the checkpoint's intruder spring of grain " +
                        std::to_string(s.ic_grain[b]) + " has no intruder candidate: not this bed");
    }
    ic_.sx[slot] = s.ic_sx[b];
    ic_.sy[slot] = s.ic_sy[b];
  }
  max_overlap_ = s.max_overlap;
  builds_ = s.builds;
  steps_on_one_ = s.steps_on_one;
  steps_on_team_ = s.steps_on_team;
  sleep_grain_steps_ = s.sleep_grain_steps;
  wake_builds_ = s.wake_builds;
  woken_ = s.woken;
  full_history_check_ = true;
  drifted_ = false;
  primed_ = true;
}

}  // namespace grainlift::dem
