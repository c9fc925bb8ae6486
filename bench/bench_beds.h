// The beds of the throughput benchmark, shared by dem_throughput, dem_state_hash and the LAMMPS
// export, and the engine set up on one of them.
#pragma once

#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/system/system_setup.h"
#include "dem_beds.h"

namespace grainlift::bench {

/// Kumar's geometry scaled down: a box of w x h mean diameters (d = 0.02 m), walls of frozen
/// disks top and bottom, periodic in x, intruder of 5 d at the origin moving at 1 m/s with
/// Omega = 2; Kumar's Table I contact law, dt = 2e-6 s. Dense: 180 d x 140 d at Phi 0.82
/// (~26,000 disks); dilute: 260 d x 200 d at Phi 0.35 (~23,000 disks); jammed: 180 d x 140 d
/// at Phi 0.86 (~27,000 disks, compressed above jamming: about two contacts per grain).
/// @p scale < 1 shrinks both sides (0.25: ~1,600 disks dense), for runs under an emulator.
inline dem::DemConfig bed_config(double phi, double scale = 1.0) {
  dem::DemConfig c = test_support::walled_bed(std::round((phi > 0.5 ? 180 : 260) * scale),
                                              std::round((phi > 0.5 ? 140 : 200) * scale), phi);
  const double d = c.grain_diameter;
  c.intruder_omega = 2.0 / (2.5 * d);
  c.dt = 2e-6;
  c.threads = 1;  // packing preparation; the benchmark sets its own thread count
  const char* dir = std::getenv("GRAINLIFT_BENCH_CACHE");
  c.packing_cache_dir = dir ? dir : "/tmp/grainlift_bench_cache";
  return c;
}

/// The engine on the prepared bed @p b of configuration @p c, as run_simulation sets it up with
/// fields off (no per-pair force store), on @p threads threads; not yet advanced.
inline std::unique_ptr<dem::DemSystem> bench_system(const dem::DemConfig& c,
                                                    const dem::PackedBed& b, int threads) {
  dem::SystemOptions o = dem::system_options(c);
  o.threads = threads;
  auto s = std::make_unique<dem::DemSystem>(o);
  s->set_bodies(dem::grain_disks(c, b.x, b.y, b.r), dem::make_wall_disks(c));
  s->set_store_pair_forces(false);
  s->set_intruder(0, 0, 0.5 * c.intruder_diameter, c.intruder_velocity[0], 0, c.intruder_omega, 0);
  return s;
}

}  // namespace grainlift::bench
