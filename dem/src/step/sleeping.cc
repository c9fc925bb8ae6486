// Sleeping grains (DemSystem::set_sleep): grains far from the intruder that are at rest, with
// neighbours at rest, leave the step until something touches them.
//
// Why no contact is missed: a sleeper does not move (v = omega = 0, and it felt no force at
// the last step, so its acceleration is the no-force value, zero without gravity). A pair of
// two sleepers (or a sleeper and a static wall disk) was apart at the build, as no sleeper
// touches anything, and stays apart while neither moves: it can leave the list. Every pair
// with an awake grain stays listed and is screened at every step, so an awake grain that
// reaches a sleeper touches it through a listed pair; the pair loop then wakes the sleeper
// (DemSystem::wake) and the lists are rebuilt before the next step, with the woken grain's
// pairs back (it has moved by one step at most, and it touched none of its fellow sleepers at
// the step it woke). With speed 0 only grains exactly at rest sleep and nothing is changed:
// the trajectories are those of a run without sleeping, bit for bit
// (Simulation.SleepingAtZeroSpeedGivesTheBitsOfARunWithout). With speed > 0 the stopped
// grains lose their slow motion: the only approximation, measured in docs/performance.md.
#include <algorithm>
#include <cmath>

#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem {

void DemSystem::wake(int i, int j) {
  for (int g : {i, j}) {
    if (g < n_grains_ && __atomic_load_n(&dormant_[g], __ATOMIC_RELAXED)) {
      __atomic_store_n(&dormant_[g], std::uint8_t{0}, __ATOMIC_RELAXED);
      __atomic_fetch_add(&woken_, 1LL, __ATOMIC_RELAXED);
      __atomic_store_n(&wake_pending_, std::uint8_t{1}, __ATOMIC_RELAXED);
    }
  }
}

void DemSystem::update_sleep() {
  if (wake_pending_) ++wake_builds_;
  wake_pending_ = 0;
  const bool on = sleep_speed_ >= 0 && opt_.gravity[0] == 0.0 && opt_.gravity[1] == 0.0 &&
                  damping_rate_ == 0.0;
  sleeping_now_ = 0;
  sleep_active_ = false;
  if (!on) return;
  const int n = n_total_;
  const double vs = sleep_speed_;
  dormant_.assign(static_cast<std::size_t>(n), 0);
  sleep_near_.assign(static_cast<std::size_t>(n), 0);  // 1: moving or near a moving body
  // quiet grains: slow, no force at the last step (accelerations are the no-force values),
  // not an intruder candidate, beyond the intruder's reach
  const double reach = intruder_.present ? (1.0 + kSleepReach) * intruder_.r + 2.0 * skin_ : 0.0;
  for (int i = 0; i < n_grains_; ++i) {
    bool quiet = std::fabs(p_.vx[i]) <= vs && std::fabs(p_.vy[i]) <= vs &&
                 std::fabs(p_.w[i]) * p_.r[i] <= vs &&
                 !(grain_flags_[i] & (kAccelSet | kCandidate));
    if (quiet && intruder_.present) {
      double dx = p_.x[i] - intruder_.x, dy = p_.y[i] - intruder_.y;
      opt_.box.min_image(dx, dy);
      const double cut = reach + p_.r[i];
      quiet = dx * dx + dy * dy >= cut * cut;
    }
    sleep_near_[i] = quiet ? 0 : 1;
  }
  // frozen disks: static walls are quiet, the lid's disks move
  for (int j = n_grains_; j < n; ++j) {
    const bool lid_disk = lid_ && j >= lid_->begin() && j < lid_->end();
    sleep_near_[j] = lid_disk ? 1 : 0;
  }
  // touching now (positions after the last drift): not quiet
  const std::size_t np = nl_.pairs();
  for (std::size_t k = 0; k < np; ++k) {
    const int i = nl_.owner[k], j = nl_.partner[k];
    double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j];
    opt_.box.min_image(dx, dy);
    const double rs = p_.r[i] + p_.r[j];
    if (dx * dx + dy * dy < rs * rs) sleep_near_[i] = sleep_near_[j] = 1;
  }
  // a moving body keeps the grains within kSleepHops list hops awake
  for (int hop = 0; hop < kSleepHops; ++hop) {
    sleep_next_ = sleep_near_;
    for (std::size_t k = 0; k < np; ++k) {
      const int i = nl_.owner[k], j = nl_.partner[k];
      if (sleep_near_[i] || sleep_near_[j]) sleep_next_[i] = sleep_next_[j] = 1;
    }
    sleep_near_.swap(sleep_next_);
  }
  for (int i = 0; i < n_grains_; ++i) {
    if (sleep_near_[i]) continue;
    dormant_[i] = 1;
    // Stopped, in the bits that a kick without force leaves unchanged, so that the kicks can
    // skip it: v = +0.0 (the kick turns -0.0 into +0.0: -0.0 + h (+0.0)); omega = +0.0 unless
    // it is -0.0 already (h alpha0 = -0.0 keeps either zero); a coordinate -0.0 becomes +0.0
    // (-0.0 + dt (+0.0)). At speed 0 these are the values the next kick would give anyway.
    p_.vx[i] = p_.vy[i] = 0.0;
    if (p_.w[i] != 0.0) p_.w[i] = 0.0;
    if (p_.x[i] == 0.0) p_.x[i] = 0.0;
    if (p_.y[i] == 0.0) p_.y[i] = 0.0;
    ++sleeping_now_;
  }
  if (sleeping_now_ == 0) return;
  for (int j = n_grains_; j < n; ++j) dormant_[j] = sleep_near_[j] ? 0 : 1;
  nl_.drop_dormant_pairs(dormant_.data());
  sleep_active_ = true;
}

}  // namespace grainlift::dem
