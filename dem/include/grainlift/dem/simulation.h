// Public entry point of the DEM engine: one run of an intruder driven through a 2D bed.
#pragma once

#include <functional>
#include <string>

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

/// What a run monitor says of the output so far.
struct MonitorVerdict {
  bool stop = false;   ///< end the run now (DemOutput::stopped_early)
  std::string status;  ///< short text for the progress line ("" for none)
};
/// Looks at the samples so far (after every progress report, at most ~100 times per run).
using RunMonitor = std::function<MonitorVerdict(const DemOutput& so_far)>;

/// @brief The same run, with @p monitor asked after every progress report whether to stop
/// (for example when the standard errors have reached a target); its status is passed to
/// @p status_progress with the fraction of the steps done.
DemOutput run_simulation(const DemConfig& cfg, const ProgressCallback& progress,
                         const RunMonitor& monitor,
                         const std::function<void(double, const std::string&)>& status_progress);

}  // namespace grainlift::dem
