// Means of a correlated time series with the standard error of block averages (Flyvbjerg and
// Petersen 1989): the series is cut into B equal blocks, each block's mean counts as one
// sample, se = sd(block means) / sqrt(B). Valid when a block is longer than the correlation
// time. The engine's own copy, since dem/ does not include shared/.
#pragma once

#include <cstddef>
#include <vector>

namespace grainlift::dem {

/// A mean and its standard error (same units as the series).
struct MeanError {
  double mean = 0;
  double se = 0;  ///< standard error of the mean
};

/// @brief Means of @p blocks equal blocks of x[begin, end) (the last end - begin mod blocks
/// values are dropped). Empty when the range holds fewer values than blocks.
std::vector<double> block_means(const std::vector<double>& x, std::size_t begin, std::size_t end,
                                int blocks);

/// @brief Mean of @p values (block means, taken as independent) and its standard error
/// sd / sqrt(n); se 0 for fewer than two values.
MeanError mean_and_error(const std::vector<double>& values);

}  // namespace grainlift::dem
