// Drag and lift by the conventions of docs/conventions.md, and block-averaged means with standard
// errors, shared by both solvers.
#pragma once

#include <cstddef>
#include <vector>

namespace grainlift {

/// Drag D = -F . V/|V| and lift L = F . (z x V/|V|) (docs/conventions.md). Forces per unit length.
struct DragLift {
  double drag = 0, lift = 0;
};
/// @param fx, fy force on the intruder (N/m); @param vx, vy intruder velocity (m/s, not zero).
DragLift project_drag_lift(double fx, double fy, double vx, double vy);

/// Mean and standard error of a correlated series from B equal blocks (the first
/// size % B samples are dropped so the blocks end at the last sample).
struct BlockMean {
  double mean = 0;
  double stderr_ = 0;   ///< standard deviation of the block means / sqrt(B)
  /// Lag-1 autocorrelation of the block means (0 with fewer than 3 blocks).
  double lag1 = 0;
  /// stderr_ corrected for a correlation between neighbouring blocks (blocks shorter than the
  /// series' correlation time): stderr_ sqrt((1 + r) / (1 - r)), r = lag1 clipped to [0, 0.9]
  /// (the AR(1) variance of a mean; never smaller than stderr_).
  double stderr_corrected = 0;
  std::size_t blocks = 0, samples = 0;
};
/// @param series samples after the steady-state start; @param blocks B >= 2 requested (fewer
/// are used when there are fewer samples than blocks; stderr is NaN with fewer than 2 blocks).
BlockMean block_mean(const std::vector<double>& series, std::size_t blocks);

}  // namespace grainlift
