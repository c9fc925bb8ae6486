// Public entry point of the DEM engine: one run of an intruder driven through a 2D bed.
#pragma once

#include <functional>

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

/// Looks at the output so far at every progress report of the run (at most ~100 times), with
/// the fraction of the steps done; returns true to end the run there (DemOutput::stopped_early).
using RunMonitor = std::function<bool(const DemOutput& so_far, double fraction)>;

/// @brief The same run, with @p monitor asked at every progress report whether to stop (for
/// example once the standard errors have reached a target). The monitor reports the run's
/// progress itself: @p progress then sees the packing phase only.
DemOutput run_simulation(const DemConfig& cfg, const ProgressCallback& progress,
                         const RunMonitor& monitor);

}  // namespace grainlift::dem
