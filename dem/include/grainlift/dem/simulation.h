// Public entry point of the DEM engine: one run of an intruder driven through a 2D bed.
#pragma once

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/errors.h"

namespace grainlift::dem {

/// @brief Check cfg (ranges, and dt against the binary collision time) without running.
/// @return the binary collision time (s) of two mean grains at the dt-check impact speed.
/// @throws ConfigError naming the offending numbers.
double validate_config(const DemConfig& cfg);

/// @brief Prepare (or load) the bed, drive the intruder through it for cfg.travel grain
/// diameters and return the sampled forces, the intruder contacts after the steady state and
/// the coarse-grained fields.
/// @param progress called with (fraction, "packing") and (fraction, "run"), at most ~100
/// times per phase.
/// @throws ConfigError for a bad configuration (dt too large, ...), RunFailure when the run
/// blows up (non-finite state, overlap above cfg.max_overlap_fraction of a diameter).
DemOutput run_simulation(const DemConfig& cfg, const ProgressCallback& progress = {});

}  // namespace grainlift::dem
