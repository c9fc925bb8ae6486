// How much a second core adds on this machine, whatever the code: four kernels, each run on
// one core alone and then as two copies side by side (one per core, pinned), and the ratio of
// the work done per second by the two copies together to the work done by one alone.
//
//   dem_core_contention [seconds per measurement (2)] [lockstep (only the lockstep rows)]
//
// A machine with two independent cores gives 2.00x on the compute kernel; two hyperthreads of
// one physical core, or a host that shares the core's time, give less. The DEM's thread and
// replica targets (issue 14: two threads >= 1.85x one, two replicas ~2x) cannot beat what
// these kernels get, so docs/performance.md quotes them beside the DEM's own ratios.
//
// A team steps in lockstep (one barrier per step: dem/src/step/team_barrier.h), so it also
// meets what a core-side ratio hides: each core's own pauses and the barrier's latency, paid
// once per step. The lockstep rows time steps of equal work per thread, from about a demo's
// step (873 grains: ~12 us per thread) to a large bed's, on two pinned threads with that
// barrier, against one thread doing both halves; their ratio is the ceiling of --threads 2 at
// that step length on this machine.
//
//   compute  eight independent multiply-add chains in registers (the FP units only)
//   cache    dependent random loads within 512 KiB (the core's L2)
//   memory   a sum over 512 MiB (the memory bandwidth the cores share)
//   store    the lockstep rows' kick-like update of each copy's own 48 kB, free-running (no
//            barrier): what the lockstep rows would give if the threads never waited
//   lockstep a kick-like update of each thread's own 48 kB of doubles per step, one barrier
//            (column "every 8": one barrier every eight steps, what a halo of eight steps
//            would allow; its ratio against the same one thread)
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "step/team_barrier.h"

namespace {

using Clock = std::chrono::steady_clock;

void pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

// One unit of each kernel; returns a value so that the work is not optimised away.
double compute_unit() {
  double a[8] = {1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7};
  for (int k = 0; k < 1 << 16; ++k)
    for (double& x : a) x = x * 0.999999 + 1e-7;
  return std::accumulate(a, a + 8, 0.0);
}

struct CacheRing {
  std::vector<std::uint32_t> next;
  explicit CacheRing(std::size_t bytes) : next(bytes / sizeof(std::uint32_t)) {
    // one random cycle through every slot: each load depends on the one before
    std::vector<std::uint32_t> order(next.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin() + 1, order.end(), std::mt19937(42));
    for (std::size_t i = 0; i < order.size(); ++i) next[order[i]] = order[(i + 1) % order.size()];
  }
  double unit(std::uint32_t& at) const {
    for (int k = 0; k < 1 << 16; ++k) at = next[at];
    return at;
  }
};

struct Stream {
  std::vector<double> data;
  explicit Stream(std::size_t bytes) : data(bytes / sizeof(double), 1.0) {}
  double unit(std::size_t& at) const {  // 1 MiB per unit, wrapping round the array
    const std::size_t n = (1u << 20) / sizeof(double);
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += data[(at + i) % data.size()];
    at = (at + n) % data.size();
    return s;
  }
};

// Units of `work` done per second on `copies` cores at once (each copy pinned to its core),
// summed over the copies.
double units_per_second(int copies, double seconds, const std::function<double(int)>& work) {
  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::vector<double> rate(copies);
  std::vector<std::thread> team;
  for (int c = 0; c < copies; ++c) {
    team.emplace_back([&, c] {
      pin_to(c);
      ++ready;
      while (!go) {
      }
      volatile double sink = 0;
      long units = 0;
      const auto t0 = Clock::now();
      double elapsed = 0;
      while (elapsed < seconds) {
        for (int k = 0; k < 16; ++k) sink = sink + work(c);
        units += 16;
        elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      }
      rate[c] = units / elapsed;
    });
  }
  while (ready < copies) {
  }
  go = true;
  for (auto& t : team) t.join();
  return std::accumulate(rate.begin(), rate.end(), 0.0);
}

/// The doubles of each of a lockstep thread's two arrays (24 kB each).
constexpr std::size_t kKickDoubles = 3 << 10;

/// One step's work of a lockstep thread: @p reps passes of a kick-like update over its arrays.
void lockstep_unit(std::vector<double>& v, const std::vector<double>& a, int reps) {
  const std::size_t n = v.size();
  for (int k = 0; k < reps; ++k)
    for (std::size_t i = 0; i < n; ++i) v[i] = 0.999 * v[i] + 1e-3 * a[i];
}

/// Seconds per step: @p threads pinned threads, each @p reps passes per step, one barrier
/// every @p every steps (threads == 1: one thread, 2 * reps passes, no barrier), for @p steps
/// steps.
double lockstep_seconds(int threads, int reps, long steps, int every = 1) {
  std::vector<std::vector<double>> v(2, std::vector<double>(kKickDoubles, 1.0));
  std::vector<std::vector<double>> a(2, std::vector<double>(kKickDoubles, 0.5));
  grainlift::dem::detail::TeamBarrier barrier(threads);
  std::atomic<int> ready{0};
  double wall = 0;
  auto body = [&](int t) {
    pin_to(t);
    ++ready;
    while (ready < threads) {
    }
    const auto t0 = Clock::now();
    for (long s = 0; s < steps; ++s) {
      lockstep_unit(v[t], a[t], threads == 1 ? 2 * reps : reps);
      if ((s + 1) % every == 0) barrier.wait();
    }
    if (t == 0) wall = std::chrono::duration<double>(Clock::now() - t0).count();
  };
  std::vector<std::thread> team;
  for (int t = 1; t < threads; ++t) team.emplace_back(body, t);
  body(0);
  for (auto& t : team) t.join();
  volatile double sink = v[0][0] + v[1][0];
  (void)sink;
  return wall / static_cast<double>(steps);
}

/// The compute, cache, memory and store kernels: one core alone, then two copies side by side.
void core_kernels(double seconds) {
  const CacheRing ring0(512 << 10), ring1(512 << 10);
  const Stream stream(std::size_t{512} << 20);
  std::uint32_t ring_at[2] = {0, 0};
  std::size_t stream_at[2] = {0, stream.data.size() / 2};
  struct Kernel {
    const char* name;
    std::function<double(int)> work;
  };
  std::vector<std::vector<double>> kick_v(2, std::vector<double>(kKickDoubles, 1.0));
  const std::vector<std::vector<double>> kick_a(2, std::vector<double>(kKickDoubles, 0.5));
  const Kernel kernels[] = {
      {"compute", [](int) { return compute_unit(); }},
      {"cache", [&](int c) { return (c ? ring1 : ring0).unit(ring_at[c]); }},
      {"memory", [&](int c) { return stream.unit(stream_at[c]); }},
      {"store",
       [&](int c) {
         lockstep_unit(kick_v[c], kick_a[c], 8);
         return kick_v[c][0];
       }},
  };
  std::printf("%-8s %16s %16s %8s\n", "kernel", "1 core (units/s)", "2 cores (units/s)", "ratio");
  for (const auto& k : kernels) {
    units_per_second(1, 0.2 * seconds, k.work);  // warm-up
    const double one = units_per_second(1, seconds, k.work);
    const double two = units_per_second(2, seconds, k.work);
    std::printf("%-8s %16.1f %16.1f %7.2fx\n", k.name, one, two, two / one);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores < 2) {
    std::printf("one core: nothing to compare\n");
    return 0;
  }
  const bool lockstep_only = argc > 2 && std::string(argv[2]) == "lockstep";
  if (argc > 2 && !lockstep_only) {
    std::fprintf(stderr, "dem_core_contention: %s: the second argument is 'lockstep' or none\n",
                 argv[2]);
    return 2;
  }
  if (!lockstep_only) core_kernels(seconds);
  // lockstep: passes per step for about 3, 12, 50 and 200 us per thread; one thread and two
  // alternately, kRounds pairs (the median of the paired ratios: a VM's slow spells last
  // seconds and change either side by tens of percent)
  constexpr int kRounds = 7;
  const double pass = lockstep_seconds(1, 50, 200) / 100;  // s per pass, one thread
  std::printf("\n%-8s %18s %18s %18s %8s %10s\n", "lockstep", "us/thread/step",
              "1 thread (us/step)", "2 threads (us/step)", "ratio", "every 8");
  for (const double us : {3.0, 12.0, 50.0, 200.0}) {
    const int reps = std::max(1, static_cast<int>(us * 1e-6 / pass + 0.5));
    const long steps =
        std::max(200L, static_cast<long>(seconds / kRounds / (2 * reps * pass)));
    lockstep_seconds(2, reps, steps / 10);  // warm-up
    std::vector<double> one, two, ratio, loose;
    for (int k = 0; k < kRounds; ++k) {
      one.push_back(lockstep_seconds(1, reps, steps));
      two.push_back(lockstep_seconds(2, reps, steps));
      ratio.push_back(one.back() / two.back());
      loose.push_back(one.back() / lockstep_seconds(2, reps, steps, 8));
    }
    auto median = [](std::vector<double> x) {
      std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
      return x[x.size() / 2];
    };
    std::printf("%-8s %18.1f %18.2f %18.2f %7.2fx %9.2fx\n", "", reps * pass * 1e6,
                median(one) * 1e6, median(two) * 1e6, median(ratio), median(loose));
  }
  return 0;
}
