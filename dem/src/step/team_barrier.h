// A barrier for the threads of one OpenMP parallel region that spins for a bounded time and
// then sleeps (Linux futex; sched_yield elsewhere).
//
// Why not "#pragma omp barrier": libgomp's default policy spins for a long time (GOMP_SPINCOUNT,
// about a millisecond) before it sleeps. When another process occupies the second core, the
// thread that is descheduled holds up the spinning one for a whole scheduler slice at every
// barrier, and the spinning thread keeps its core from the process that displaced its partner:
// two threads ran 60x slower than one. OMP_WAIT_POLICY=passive avoids that but sleeps at every
// barrier, which cost 45% on an idle machine. This barrier spins for about kSpinNs = 20 us
// (two to four chunks of work: about the imbalance of one phase of a step, whose chunks are
// handed out dynamically), then sleeps, and the last thread to arrive wakes the sleepers only when
// there are any. Under a load of 8 to 10 on two cores, 10 to 20 us were 2 to 3x faster than
// 50 us and 5 to 10x faster than 1 ms (docs/performance.md).
#pragma once

#include <atomic>
#include <chrono>
#include <climits>
#include <cstdlib>

#if defined(__linux__)
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif
#include <sched.h>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace grainlift::dem::detail {

class TeamBarrier {
 public:
  /// Spin for about this long before sleeping (see docs/performance.md); the environment
  /// variable GRAINLIFT_BARRIER_SPIN_US overrides it (0: sleep at once, like
  /// OMP_WAIT_POLICY=passive).
  static constexpr long long kSpinNs = 20000;

  explicit TeamBarrier(int threads) : threads_(threads), spin_ns_(spin_ns()) {}

  /// @brief Wait for all threads; the last one to arrive runs on_release() before it lets the
  /// others go (with the memory effects of all threads before the barrier visible to it).
  template <class F>
  void wait(F&& on_release) {
    if (threads_ == 1) {
      on_release();
      return;
    }
    const unsigned g = gen_.load(std::memory_order_acquire);
    if (count_.fetch_add(1, std::memory_order_acq_rel) == threads_ - 1) {
      count_.store(0, std::memory_order_relaxed);
      on_release();
      gen_.fetch_add(1, std::memory_order_seq_cst);
      if (sleepers_.load(std::memory_order_seq_cst) > 0) wake_all();
      return;
    }
    // spin: check the clock every 64 polls
    const auto t0 = std::chrono::steady_clock::now();
    for (int n = 1;; ++n) {
      if (gen_.load(std::memory_order_acquire) != g) return;
      pause();
      if ((n & 63) == 0 &&
          std::chrono::steady_clock::now() - t0 > std::chrono::nanoseconds(spin_ns_)) {
        break;
      }
    }
    sleepers_.fetch_add(1, std::memory_order_seq_cst);
    while (gen_.load(std::memory_order_seq_cst) == g) sleep_while(g);
    sleepers_.fetch_sub(1, std::memory_order_relaxed);
  }

  void wait() {
    wait([] {});
  }

 private:
  static long long spin_ns() {
    static const long long ns = [] {
      const char* e = std::getenv("GRAINLIFT_BARRIER_SPIN_US");
      return e ? static_cast<long long>(std::atof(e) * 1000.0) : kSpinNs;
    }();
    return ns;
  }
  static void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
  }
  void sleep_while(unsigned g) {
#if defined(__linux__)
    syscall(SYS_futex, reinterpret_cast<unsigned*>(&gen_), FUTEX_WAIT_PRIVATE, g, nullptr,
            nullptr, 0);
#else
    (void)g;
    sched_yield();
#endif
  }
  void wake_all() {
#if defined(__linux__)
    syscall(SYS_futex, reinterpret_cast<unsigned*>(&gen_), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr,
            nullptr, 0);
#endif
  }

  const int threads_;
  const long long spin_ns_;
  alignas(64) std::atomic<int> count_{0};
  alignas(64) std::atomic<unsigned> gen_{0};
  alignas(64) std::atomic<int> sleepers_{0};
};

static_assert(sizeof(std::atomic<unsigned>) == sizeof(unsigned), "futex word");

}  // namespace grainlift::dem::detail
