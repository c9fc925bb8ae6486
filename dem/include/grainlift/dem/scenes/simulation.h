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

/// @brief The steps of a run of @p cfg: its travel (grain diameters) at the intruder's speed,
/// rounded up to whole steps of cfg.dt.
long long travel_steps(const DemConfig& cfg);

/// @brief The configuration a run of @p cfg prepares its bed with: cfg with dt no larger than
/// 0.1 of the binary collision time (validate_config), whatever dt the run itself uses, so
/// that runs, exports and their cache entries share one bed. @throws ConfigError as
/// validate_config.
DemConfig packing_config(const DemConfig& cfg);

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

struct RunCheckpoint;  // checkpoint.h

/// Checkpoints and interruption of a run (every member optional).
struct RunControl {
  /// Go on from this checkpoint, taken by a run of the same configuration, instead of
  /// preparing a bed: the samples, contacts, fields and forces that follow are those the
  /// uninterrupted run gives, bit for bit (with dem.sleep_speed = 0, the default).
  const RunCheckpoint* resume = nullptr;
  /// Receives a checkpoint at the first event (force sample, field snapshot, progress report)
  /// after every checkpoint_steps steps and after every checkpoint_seconds of wall time (0:
  /// neither), and when interrupted() says so; never at the end of the run.
  std::function<void(const RunCheckpoint&)> checkpoint;
  long long checkpoint_steps = 0;
  double checkpoint_seconds = 0;
  /// Asked at every event: true ends the run there, after a checkpoint
  /// (DemOutput::interrupted, stopped_early).
  std::function<bool()> interrupted;
};

/// @brief The same run with checkpoints, interruption and resumption (RunControl).
/// @throws ConfigError also when @p control.resume is of another run length or bed.
DemOutput run_simulation(const DemConfig& cfg, const ProgressCallback& progress,
                         const RunMonitor& monitor, const RunControl& control);

}  // namespace grainlift::dem
