// Bit-identity check of the DEM step: runs the benchmark beds (dense, dilute, jammed) on 1 and
// 2 threads and prints a hash (FNV-1a over every bit) of the state: positions, velocities,
// accelerations of all grains, the tangential history of every listed pair (by grain pair),
// the intruder force and torque and the largest overlap fraction. Run it with two builds to
// check that a change keeps the results bit for bit; the 1- and 2-thread lines must agree.
//
//   ./build/bin/dem_state_hash [steps (3000)] [beds (dense,dilute,jammed)] [threads (1,2)]
//                              [scale (1)]
//
// The last two are for runs under an emulator (tests/other_cpus/): "1" leaves out the team
// (qemu-aarch64 7.2 cannot start a second thread), a scale below 1 shrinks the beds' sides.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bench_beds.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/step/vector_kernels.h"

namespace gd = grainlift::dem;

namespace {

struct Fnv {
  std::uint64_t h = 1469598103934665603ULL;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= b[i];
      h *= 1099511628211ULL;
    }
  }
  void d(double v) { add(&v, sizeof v); }
  void i(long long v) { add(&v, sizeof v); }
};

std::uint64_t run(double phi, double scale, int threads, long long steps) {
  gd::DemConfig c = grainlift::bench::bed_config(phi, scale);
  const gd::PackedBed b = gd::prepare_packing(c);
  const auto sys = grainlift::bench::bench_system(c, b, threads);
  gd::DemSystem& s = *sys;
  Fnv f;
  // single steps, then advance() in blocks (the fused path), intruder samples on the way
  long long done = 0;
  for (; done < steps / 10; ++done) s.step();
  while (done < steps) {
    s.advance(50);
    done += 50;
    f.d(s.intruder_fx());
    f.d(s.intruder_fy());
    f.d(s.intruder_torque());
    f.d(s.take_max_overlap_fraction());
  }
  const auto& p = s.particles();
  for (int i = 0; i < s.grains(); ++i) {
    for (const auto* v : {&p.x, &p.y, &p.vx, &p.vy, &p.w, &p.ax, &p.ay, &p.alpha}) f.d((*v)[i]);
  }
  const auto& nl = s.neighbors();
  for (int i = 0; i < s.grains(); ++i) {
    for (auto k = nl.first[i]; k < nl.first[i + 1]; ++k) {
      if (nl.sx[k] == 0.0 && nl.sy[k] == 0.0) continue;
      f.i(i);
      f.i(nl.partner[k]);
      f.d(nl.sx[k]);
      f.d(nl.sy[k]);
    }
  }
  f.i(s.list_builds());
  return f.h;
}

}  // namespace

int main(int argc, char** argv) {
  const long long steps = argc > 1 ? std::atoll(argv[1]) : 3000;
  const std::string beds = argc > 2 ? argv[2] : "dense,dilute,jammed";
  const std::string teams = argc > 3 ? argv[3] : "1,2";
  // the thread counts to run: "1", "2" or "1,2"
  const bool with[2] = {teams == "1" || teams == "1,2", teams == "2" || teams == "1,2"};
  if (!with[0] && !with[1]) {
    std::fprintf(stderr, "dem_state_hash: threads %s: give 1, 2 or 1,2\n", teams.c_str());
    return 2;
  }
  const double scale = argc > 4 ? std::atof(argv[4]) : 1.0;
  if (!(scale > 0.05 && scale <= 1.0)) {
    std::fprintf(stderr, "dem_state_hash: scale %s: give a number in (0.05, 1]\n", argv[4]);
    return 2;
  }
  struct {
    const char* name;
    double phi;
  } all[] = {{"dense", 0.82}, {"dilute", 0.35}, {"jammed", 0.86}};
  // the target on stderr, so that stdout stays the same text on every target
  if (const std::string e = gd::simd_setting_error(); !e.empty()) {
    std::fprintf(stderr, "%s\n", e.c_str());
    return 2;
  }
  std::fprintf(stderr, "simd target: %s (this build and CPU: %s)\n", gd::simd_target().c_str(),
               gd::simd_targets().c_str());
  int bad = 0;
  for (const auto& bd : all) {
    if (beds.find(bd.name) == std::string::npos) continue;
    std::uint64_t h[2] = {0, 0};
    for (int t = 1; t <= 2; ++t) {
      if (!with[t - 1]) continue;
      h[t - 1] = run(bd.phi, scale, t, steps);
      std::printf("%-7s threads %d steps %lld: %016" PRIx64 "\n", bd.name, t, steps, h[t - 1]);
      std::fflush(stdout);
    }
    if (with[0] && with[1] && h[0] != h[1]) ++bad;
  }
  if (bad) std::printf("1 and 2 threads DIFFER on %d bed(s)\n", bad);
  return bad ? 1 : 0;
}
