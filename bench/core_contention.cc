// How much a second core adds on this machine, whatever the code: three kernels, each run on
// one core alone and then as two copies side by side (one per core, pinned), and the ratio of
// the work done per second by the two copies together to the work done by one alone.
//
//   dem_core_contention [seconds per measurement (2)]
//
// A machine with two independent cores gives 2.00x on the compute kernel; two hyperthreads of
// one physical core, or a host that shares the core's time, give less. The DEM's thread and
// replica targets (issue 14: two threads >= 1.85x one, two replicas ~2x) cannot beat what
// these kernels get, so docs/performance.md quotes them beside the DEM's own ratios.
//
//   compute  eight independent multiply-add chains in registers (the FP units only)
//   cache    dependent random loads within 512 KiB (the core's L2)
//   memory   a sum over 512 MiB (the memory bandwidth the cores share)
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

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

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores < 2) {
    std::printf("one core: nothing to compare\n");
    return 0;
  }
  const CacheRing ring0(512 << 10), ring1(512 << 10);
  const Stream stream(std::size_t{512} << 20);
  std::uint32_t ring_at[2] = {0, 0};
  std::size_t stream_at[2] = {0, stream.data.size() / 2};
  struct Kernel {
    const char* name;
    std::function<double(int)> work;
  };
  const Kernel kernels[] = {
      {"compute", [](int) { return compute_unit(); }},
      {"cache", [&](int c) { return (c ? ring1 : ring0).unit(ring_at[c]); }},
      {"memory", [&](int c) { return stream.unit(stream_at[c]); }},
  };
  std::printf("%-8s %16s %16s %8s\n", "kernel", "1 core (units/s)", "2 cores (units/s)", "ratio");
  for (const auto& k : kernels) {
    units_per_second(1, 0.2 * seconds, k.work);  // warm-up
    const double one = units_per_second(1, seconds, k.work);
    const double two = units_per_second(2, seconds, k.work);
    std::printf("%-8s %16.1f %16.1f %7.2fx\n", k.name, one, two, two / one);
  }
  return 0;
}
