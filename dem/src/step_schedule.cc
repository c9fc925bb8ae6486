// How the steps of advance() run: one thread in a plain loop (run_segment), or a team of
// threads on work items that wait only for the items they depend on (run_segment_team).
#include <algorithm>
#include <atomic>
#include <cmath>

#include <omp.h>
#include <sched.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "grainlift/dem/dem_system.h"
#include "team_barrier.h"

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
    intruder_forces(dt, max_ov);
    for (int c = 0; c < chunks(); ++c) chunk_forces(c, dt, max_ov, full_history_check_);
    ++k;
    const bool last = k == m;
    step_boundaries();
    advance_clock(last, idisp);
    full_history_check_ = false;
    d2 = 0;
    for (int c = 0; c < chunks(); ++c) {
      const int lo = c * kChunkRows;
      d2 = std::max(d2, finish_rows(lo, std::min(n_grains_, lo + kChunkRows),
                                    last ? Kick::sync : Kick::drift));
    }
    if (last) break;
  }
  max_overlap_ = max_ov;
  drifted_ = rebuild;
  return k;
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

// The threaded step without a team barrier inside the segment. Work items, one sequence for all
// steps, handed out from one counter: per step, the pair forces (item 0: the intruder's
// contacts, 1 + c: the pairs owned by chunk c), then the kicks (item 0: the intruder's motion
// and the clock, 1 + c: the grains of chunk c). A force item of step s waits until every kick
// item of step s - 1 is done and the list check for step s is taken (by the thread that
// completed the last of them, from the per-item displacements); a kick item of chunk c waits
// only for the force items that read or add to its grains (chunks kick_dep_[c] to c, and the
// intruder). A thread that is descheduled holds up the others only through the items it holds,
// not by having to arrive at a barrier. The operations, and so the bits, are those of
// run_segment (every per-grain sum is taken in pair order at the kick, whoever computed the
// pair forces).
long long DemSystem::run_segment_team(long long m) {
  const int team = team_;
  const int nchunks = chunks();
  const int per_phase = nchunks + 1;
  const long long per_step = 2LL * per_phase;
  const double dt = opt_.dt;
  const int ng = n_grains_;
  const int rows_per_chunk = kChunkRows;
  detail::TeamBarrier barrier(team);
  std::atomic<int> init_next{0};
  std::atomic<long long> next{0};
  std::atomic<long long> kicks_done{0};  // kick items completed in this segment
  std::atomic<long long> decided{-1};    // list check taken for steps <= decided
  std::atomic<long long> stop_step{m};   // first step not to run (a rebuild is due)
  std::atomic<long long>* fdone = force_done_.get();
  for (int q = 0; q < per_phase; ++q) fdone[q].store(0, std::memory_order_relaxed);
  double* kd2 = kick_d2_.data();
  struct alignas(64) Slot {
    double d2 = 0;
  };
  Slot slot[kMaxTeam];
  double idisp = 0;
  const bool was_drifted = drifted_;
  const bool full_check0 = full_history_check_;
  double max_ov = max_overlap_;
#pragma omp parallel num_threads(team) reduction(max : max_ov)
  {
    const int t = omp_get_thread_num();
    double d2 = 0;
    if (!was_drifted) {
      for (int c; (c = init_next.fetch_add(1, std::memory_order_relaxed)) < per_phase;)
        d2 = std::max(d2, drift_item(c, idisp));
    }
    slot[t].d2 = d2;
    barrier.wait([] {});
    if (t == 0) {
      double md2 = 0;
      for (int u = 0; u < team; ++u) md2 = std::max(md2, slot[u].d2);
      if (rebuild_due(md2, idisp, was_drifted)) stop_step.store(0, std::memory_order_relaxed);
      decided.store(0, std::memory_order_release);
    }
    for (;;) {
      const long long g = next.fetch_add(1, std::memory_order_relaxed);
      const long long s = g / per_step;
      const int idx = static_cast<int>(g % per_step);
      if (s >= m) break;
      if (idx < per_phase) {
        // pair forces of step s
        wait_until([&] { return decided.load(std::memory_order_acquire) >= s; });
        if (s >= stop_step.load(std::memory_order_relaxed)) break;
        if (idx == 0) {
          intruder_forces(dt, max_ov);
        } else {
          chunk_forces(idx - 1, dt, max_ov, s == 0 && full_check0);
        }
        fdone[idx].store(s + 1, std::memory_order_release);
      } else {
        // kicks of step s
        const int c = idx - per_phase;
        const bool last = s == m - 1;
        wait_until([&] { return fdone[0].load(std::memory_order_acquire) > s; });
        if (c == 0) {
          advance_clock(last, idisp);
        } else {
          for (int q = kick_dep_[c - 1]; q <= c - 1; ++q) {
            wait_until([&] { return fdone[q + 1].load(std::memory_order_acquire) > s; });
          }
          const int lo = (c - 1) * rows_per_chunk;
          kd2[c] = finish_rows(lo, std::min(ng, lo + rows_per_chunk),
                               last ? Kick::sync : Kick::drift);
        }
        // the thread that completes the step (every force item of the step is done: each
        // kick item waited for its own chunk's) moves the boundaries and takes the list check
        // for the next step
        if (kicks_done.fetch_add(1, std::memory_order_acq_rel) == (s + 1) * per_phase - 1) {
          step_boundaries();
          if (!last) {
            double md2 = 0;
            for (int q = 1; q <= nchunks; ++q) md2 = std::max(md2, kd2[q]);
            if (rebuild_due(md2, idisp, false)) stop_step.store(s + 1, std::memory_order_relaxed);
            decided.store(s + 1, std::memory_order_release);
          }
        }
      }
    }
  }
  const long long completed = std::min(m, stop_step.load());
  if (completed > 0) full_history_check_ = false;
  max_overlap_ = max_ov;
  drifted_ = completed < m;
  return completed;
}


}  // namespace grainlift::dem
