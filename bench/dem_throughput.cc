// DEM throughput: particle-steps per second of the full time step (neighbour lists, contact
// law, intruder loop, integration) for a dense (Phi 0.82) and a dilute (Phi 0.35) bed of
// more than 20,000 disks, both relaxed below jamming (almost no contacts), and a jammed bed
// (Phi 0.86, about two contacts per grain), on 1 and 2 threads. The intruder moves at 1 m/s with
// Omega = 2, Kumar's parameters and dt = 2e-6 s. Beds are prepared once and cached under
// $GRAINLIFT_BENCH_CACHE (default: /tmp/grainlift_bench_cache).
//
//   ./build-dem/bin/dem_throughput --benchmark_counters_tabular=true
//   GRAINLIFT_BENCH_STEPS=2000 ./build-dem/bin/dem_throughput   # exactly 2000 timed steps
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>

#include "bench_beds.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/step/vector_kernels.h"

namespace gd = grainlift::dem;

namespace {

using grainlift::bench::bed_config;

const gd::PackedBed& bed(double phi) {
  static std::map<double, gd::PackedBed> beds;
  auto it = beds.find(phi);
  if (it == beds.end()) it = beds.emplace(phi, gd::prepare_packing(bed_config(phi))).first;
  return it->second;
}

void run_bed(benchmark::State& state, double phi) {
  gd::DemConfig c = bed_config(phi);
  const gd::PackedBed& b = bed(phi);
  const auto sys = grainlift::bench::bench_system(c, b, static_cast<int>(state.range(0)));
  gd::DemSystem& s = *sys;
  s.advance(500);  // warm-up: lists built, intruder in contact
  const int builds0 = s.list_builds();
  const int steps_per_iteration = 100;
  for (auto _ : state) {
    s.advance(steps_per_iteration);
  }
  const double ps = static_cast<double>(state.iterations()) * steps_per_iteration * s.grains();
  state.counters["particle_steps_per_s"] = benchmark::Counter(ps, benchmark::Counter::kIsRate);
  state.counters["grains"] = s.grains();
  state.counters["pairs_per_grain"] =
      static_cast<double>(s.neighbors().pairs()) / std::max(1, s.grains());
  // pairs in contact at the end (the beds below jamming have almost none)
  {
    const auto& nl = s.neighbors();
    const auto& p = s.particles();
    long touching = 0;
    for (int i = 0; i < s.grains(); ++i) {
      for (auto k = nl.first[i]; k < nl.first[i + 1]; ++k) {
        const int j = nl.partner[k];
        double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j];
        s.box().min_image(dx, dy);
        if (std::sqrt(dx * dx + dy * dy) < p.r[i] + p.r[j]) ++touching;
      }
    }
    state.counters["contacts_per_grain"] = static_cast<double>(touching) / std::max(1, s.grains());
  }
  state.counters["steps_per_rebuild"] =
      static_cast<double>(state.iterations()) * steps_per_iteration /
      std::max(1, s.list_builds() - builds0);
}

void BM_DenseBed(benchmark::State& state) { run_bed(state, 0.82); }
void BM_DiluteBed(benchmark::State& state) { run_bed(state, 0.35); }
void BM_JammedBed(benchmark::State& state) { run_bed(state, 0.86); }

}  // namespace

// GRAINLIFT_BENCH_STEPS=n times exactly n steps after the warm-up (n / 100 iterations; the
// LAMMPS comparison sets it to LAMMPS's timed steps, so that both codes time the same steps of
// the same bed); unset, each benchmark runs for at least 3 s (the intruder then ploughs
// further and the dense bed gathers more contacts the faster the code is).
int main(int argc, char** argv) {
  // the vector target of the step (GRAINLIFT_SIMD chooses), in the benchmark's context lines
  benchmark::AddCustomContext("grainlift_simd", grainlift::dem::simd_target());
  const char* steps = std::getenv("GRAINLIFT_BENCH_STEPS");
  const long iterations = steps ? std::max(1L, std::atol(steps) / 100) : 0;
  struct {
    const char* name;
    void (*fn)(benchmark::State&);
  } beds[] = {
      {"BM_DenseBed", BM_DenseBed}, {"BM_DiluteBed", BM_DiluteBed}, {"BM_JammedBed", BM_JammedBed}};
  for (const auto& b : beds) {
    auto* r = benchmark::RegisterBenchmark(b.name, b.fn);
    r->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
    if (iterations > 0) {
      r->Iterations(iterations);
    } else {
      r->MinTime(3.0);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
