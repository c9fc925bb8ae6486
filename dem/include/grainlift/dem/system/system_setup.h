// A case's engine: the options, grain disks and bodies of a DemSystem built from a DemConfig,
// written once for the packing, the run, the benchmarks and the tests.
#pragma once

#include <memory>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem {

/// @brief The case's box (m) and its periodic directions.
PeriodicBox box_of(const DemConfig& cfg);

/// @brief The engine options of the case: box, contact law, time step (s), threads, gravity.
SystemOptions system_options(const DemConfig& cfg);

/// @brief Grains at rest at (x, y) (m) with radii r (m) and mass density pi r^2 (kg).
std::vector<Disk> grain_disks(const DemConfig& cfg, const std::vector<double>& x,
                              const std::vector<double>& y, const std::vector<double>& r);

/// @brief The engine of the case on the prepared @p bed: its grains and the wall disks of
/// make_wall_disks(); no intruder, no lid, not yet prepared.
std::unique_ptr<DemSystem> system_on_bed(const DemConfig& cfg, const PackedBed& bed);

}  // namespace grainlift::dem
