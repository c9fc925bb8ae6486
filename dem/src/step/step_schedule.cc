// How the steps of advance() run: one thread in a plain loop (run_segment), or a team of
// threads, each on its own range of rows, one barrier per step (run_segment_team).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include <omp.h>
#include <sched.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "grainlift/dem/system/dem_system.h"
#include "step/team_barrier.h"

namespace grainlift::dem {

bool DemSystem::rebuild_due(double max_d2, double intruder_disp, bool fresh) const {
  // Right after a build (re-entry after a rebuild) the lists are fresh whatever the bound
  // says; without this a box so large that the float rounding of the build positions
  // (build_round_) exceeded skin / 2 would rebuild forever instead of every step.
  if (fresh) return false;
  // a sleeper woke: its pairs with other sleepers must be listed before it moves again
  if (__atomic_load_n(&wake_pending_, __ATOMIC_RELAXED)) return true;
  const double md = std::sqrt(max_d2) + build_round_ + growth_since_build_;
  return 2.0 * md > skin_ || intruder_disp + md > skin_;
}

void DemSystem::advance_clock(bool last, double& intruder_disp) {
  time_ += opt_.dt;
  ++steps_;
  if (!last) intruder_disp = drift_intruder();
}

// One thread: per step the pair forces (the intruder's contacts, then the chunks in order),
// then the boundaries, the clock and the kicks; the list check before every step.
long long DemSystem::run_segment(long long m) {
  const double dt = opt_.dt;
  const bool was_drifted = drifted_;
  double idisp = 0, d2 = 0;
  if (!was_drifted) {
    for (int c = 0; c <= chunks(); ++c) d2 = std::max(d2, drift_item(c, idisp));
  }
  double max_ov = max_overlap_;
  long long k = 0;
  bool rebuild = false;
  for (;;) {
    if (rebuild_due(d2, idisp, was_drifted && k == 0)) {
      rebuild = true;
      break;
    }
    const bool last = k + 1 == m;
    intruder_forces(dt, max_ov);
    for (int c = 0; c < chunks(); ++c) chunk_forces(c, dt, max_ov, full_history_check_, last);
    ++k;
    step_boundaries();
    advance_clock(last, idisp);
    full_history_check_ = false;
    d2 = 0;
    for (int c = 0; c < chunks(); ++c) {
      const int lo = c * kChunkRows;
      d2 = std::max(d2, finish_rows(lo, std::min(n_grains_, lo + kChunkRows),
                                    last ? Kick::sync : Kick::drift, false));
    }
    if (last) break;
  }
  max_overlap_ = max_ov;
  drifted_ = rebuild;
  return k;
}

void DemSystem::plan_split() {
  const int team = team_;
  const int ng = n_grains_;
  const std::int64_t* first = nl_.first.data();
  const int* partner = nl_.partner.data();
  // The work of a row: its kick, the screen of its listed pairs, the contact law of those
  // that touch now (relative costs measured on one thread: a screened pair ~1, a contact
  // ~kContactCost, a kick ~kRowCost).
  constexpr double kRowCost = 2.0, kContactCost = 12.0;
  std::vector<double> cum(static_cast<std::size_t>(ng) + 1, 0.0);
  for (int i = 0; i < ng; ++i) {
    cum[static_cast<std::size_t>(i) + 1] = kRowCost + static_cast<double>(first[i + 1] - first[i]);
  }
  for_each_gap([&](double delta, double, double, int i, int j) {
    if (j >= 0 && delta > 0) cum[static_cast<std::size_t>(i) + 1] += kContactCost;
  });
  for (int i = 0; i < ng; ++i)
    cum[static_cast<std::size_t>(i) + 1] += cum[static_cast<std::size_t>(i)];
  // Each thread's speed from the last plan (work per busy second), averaged over plans; equal
  // speeds at first.
  const auto nt = static_cast<std::size_t>(team);
  if (split_speed_.size() != nt) {
    split_speed_.assign(nt, 1.0);
  } else if (split_work_.size() == nt && split_steps_ >= 50) {
    for (std::size_t t = 0; t < nt; ++t) {
      if (!(split_busy_[t] > 0) || !(split_work_[t] > 0)) continue;
      const double v = split_work_[t] * static_cast<double>(split_steps_) / split_busy_[t];
      split_speed_[t] = 0.5 * split_speed_[t] + 0.5 * v;
    }
  }
  double speed_sum = 0;
  for (double v : split_speed_) speed_sum += v;
  split_.assign(nt + 1, ng);
  split_[0] = 0;
  double share = 0;
  for (int t = 1; t < team; ++t) {
    share += split_speed_[static_cast<std::size_t>(t) - 1] / speed_sum;
    const double goal = cum[static_cast<std::size_t>(ng)] * share;
    const auto it = std::lower_bound(cum.begin(), cum.end(), goal);
    split_[static_cast<std::size_t>(t)] =
        std::max(split_[static_cast<std::size_t>(t) - 1],
                 std::min(ng, static_cast<int>(it - cum.begin())));
  }
  // Each range [lo, hi) has a top band [cross, hi): the rows from the first one that owns a
  // pair reaching a higher range. Its pairs are computed first, so that the higher ranges may
  // kick the rows those pairs read as early as possible. Shared grains (summed at the kick
  // from the stored pair forces, in pair order, whatever the order the pairs were computed
  // in): the partners of a pair owned by a lower range, and those of the top band reached by
  // the rows of their own range below the band. The pairs of the lower ranges reach the rows
  // [lo, split_reach_[t]) of range t.
  shared_.assign(static_cast<std::size_t>(ng), 0);
  split_cross_.assign(split_.begin() + 1, split_.end());
  split_reach_.assign(split_.begin(), split_.end() - 1);
  for (std::size_t t = 0; t < nt; ++t) {
    const int lo = split_[t], hi = split_[t + 1];
    int& cross = split_cross_[t];
    for (int i = lo; i < hi; ++i) {
      for (std::int64_t k = first[i]; k < first[i + 1]; ++k) {
        const int j = partner[k];
        if (j >= hi && j < ng) {
          shared_[static_cast<std::size_t>(j)] = 1;
          cross = std::min(cross, i);
          // the range of j, and the rows of it that lower ranges reach
          const auto u = static_cast<std::size_t>(
              std::upper_bound(split_.begin(), split_.end(), j) - split_.begin() - 1);
          split_reach_[u] = std::max(split_reach_[u], j + 1);
        }
      }
    }
    for (std::int64_t k = first[lo]; k < first[cross]; ++k) {
      const int j = partner[k];
      if (j >= cross && j < hi) shared_[static_cast<std::size_t>(j)] = 1;
    }
  }
  shared_rows_.clear();
  for (int i = 0; i < ng; ++i)
    if (shared_[static_cast<std::size_t>(i)]) shared_rows_.push_back(i);
  // two touch lists per thread: the top band, then the rest, each with room for all its pairs
  split_touch_.resize(2 * nt);
  split_touch_prev_.resize(2 * nt);
  auto size_lists = [&](std::size_t l, int row_lo, int row_hi) {
    const auto np = static_cast<std::size_t>(first[row_hi] - first[row_lo]);
    split_touch_[l].size_for(np);
    split_touch_prev_[l].size_for(np);
  };
  for (std::size_t t = 0; t < nt; ++t) {
    size_lists(2 * t, split_cross_[t], split_[t + 1]);
    size_lists(2 * t + 1, split_[t], split_cross_[t]);
  }
  split_work_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    split_work_[t] =
        cum[static_cast<std::size_t>(split_[t + 1])] - cum[static_cast<std::size_t>(split_[t])];
  }
  split_busy_.assign(nt, 0.0);
  split_steps_ = 0;
  full_history_check_ = true;  // new touch lists: the next force pass checks every pair
  split_build_ = builds_;
}

namespace {
/// Spin (then yield) until ready() holds.
template <class Ready>
inline void wait_until(Ready ready) {
  for (int n = 0; !ready(); ++n) {
    if (n < 2000) {
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();
#endif
    } else {
      sched_yield();
    }
  }
}
}  // namespace

// The threaded step. Thread t owns the rows [split_[t], split_[t + 1]): it computes the
// pair forces of their top band first (the pairs that reach higher ranges; thread 0 the
// intruder's contacts before), then of the other rows, then kicks the rows of its range that
// no lower range reads, then - once the lower ranges have their top bands' forces - the rows
// they read (a pair's partner is never below its owner: no range waits for a higher one). At
// the one barrier of the step the last thread to arrive moves the boundaries and the clock
// and takes the list check for the next step. A grain reached only by pairs of one pass of
// its own thread gets its sum in the pair loop, as on one thread; a shared grain (plan_split)
// gets it at the kick from the stored pair forces, in pair order: the same bits as
// run_segment, whatever the split.
long long DemSystem::run_segment_team(long long m) {
  if (split_build_ != builds_ || static_cast<int>(split_.size()) != team_ + 1) plan_split();
  const int team = team_;
  const double dt = opt_.dt;
  const std::uint8_t* shared = shared_.data();
  detail::TeamBarrier barrier(team);
  struct alignas(64) Slot {
    double d2 = 0;
    double busy = 0;  ///< s, pair forces and kicks
    std::atomic<long long> band_done{0};  ///< steps of this segment with the top band's forces
    std::atomic<long long> intruder_done{0};  ///< the same for the intruder's (thread 0)
  };
  Slot slot[kMaxTeam];
  double idisp = 0;
  const bool was_drifted = drifted_;
  // written only in the barrier's release, read by every thread after it
  bool full_check = full_history_check_;
  long long completed = 0;
  bool done = false, rebuild = false;
  double max_ov = max_overlap_;
  auto largest_d2 = [&] {
    double md2 = 0;
    for (int u = 0; u < team; ++u) md2 = std::max(md2, slot[u].d2);
    return md2;
  };
#pragma omp parallel num_threads(team) reduction(max : max_ov)
  {
    const int t = omp_get_thread_num();
    const int lo = split_[static_cast<std::size_t>(t)];
    const int hi = split_[static_cast<std::size_t>(t) + 1];
    const auto ut = static_cast<std::size_t>(t);
    const int cross = split_cross_[ut];
    const int reach = t > 0 ? split_reach_[ut] : hi;
    if (!was_drifted) {
      slot[t].d2 = drift_rows(lo, hi);
      if (t == 0) idisp = drift_intruder();
    }
    barrier.wait([&] {
      rebuild = rebuild_due(was_drifted ? 0.0 : largest_d2(), idisp, was_drifted);
      done = rebuild;
    });
    using Clock = std::chrono::steady_clock;
    Clock::duration busy{0};
    for (long long s = 0; !done; ++s) {
      const auto t0 = Clock::now();
      if (t == 0) {
        intruder_forces(dt, max_ov);
        slot[0].intruder_done.store(s + 1, std::memory_order_release);
      }
      const bool last = s + 1 == m;
      range_forces(cross, hi, split_touch_[2 * ut], split_touch_prev_[2 * ut], dt, max_ov,
                   full_check, last, shared);
      slot[t].band_done.store(s + 1, std::memory_order_release);
      range_forces(lo, cross, split_touch_[2 * ut + 1], split_touch_prev_[2 * ut + 1], dt,
                   max_ov, full_check, last, shared);
      const Kick mode = last ? Kick::sync : Kick::drift;
      double d2 = 0;
      if (t > 0) {
        // the rows no lower range reaches, once the intruder's contacts are known
        wait_until([&] { return slot[0].intruder_done.load(std::memory_order_acquire) > s; });
        d2 = finish_rows(reach, hi, mode, true);
      }
      const auto t1 = Clock::now();
      for (int u = 0; u < t; ++u) {
        wait_until([&] { return slot[u].band_done.load(std::memory_order_acquire) > s; });
      }
      const auto t2 = Clock::now();
      slot[t].d2 = std::max(d2, finish_rows(lo, reach, mode, true));
      busy += (t1 - t0) + (Clock::now() - t2);
      barrier.wait([&] {
        completed = s + 1;
        step_boundaries();
        advance_clock(last, idisp);
        full_check = false;
        if (last) {
          done = true;
        } else if (rebuild_due(largest_d2(), idisp, false)) {
          done = rebuild = true;
        }
      });
    }
    slot[t].busy = std::chrono::duration<double>(busy).count();
  }
  for (int u = 0; u < team; ++u) split_busy_[static_cast<std::size_t>(u)] += slot[u].busy;
  split_steps_ += completed;
  full_history_check_ = full_check;
  max_overlap_ = max_ov;
  drifted_ = rebuild;
  return completed;
}

}  // namespace grainlift::dem
