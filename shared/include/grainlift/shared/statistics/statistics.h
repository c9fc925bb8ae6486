// The statistics of grainlift's results, one rule each: block means of a correlated time series
// with the correlation-corrected error, the pooled mean of independent beds, and Richardson
// extrapolation over three mesh levels.
//
// Its own library, grainlift_statistics, with no dependency beyond the standard library (no
// deal.II, HDF5 or TOML): the DEM engine links it and still knows nothing of TOML, HDF5 or the
// continuum engine. grainlift_shared re-exports it. python/grainlift/stats.py is its Python
// mirror (same rules, edge cases and order of the sums), pinned equal to 1e-12 relative by
// tests/scripts/test_statistics_equal.py: change one only together with the other.
#pragma once

#include <cstddef>
#include <vector>

namespace grainlift {

/// Mean and standard errors of a correlated series (block_mean()).
struct BlockMean {
  double mean = 0;     ///< mean of the block means (= mean of the samples used)
  double stderr_ = 0;  ///< sd(block means, n - 1) / sqrt(B); NaN with fewer than 2 blocks
  /// Lag-1 autocorrelation of the block means, sum (m_b - m)(m_{b+1} - m) / sum (m_b - m)^2
  /// (0 with fewer than 3 blocks or equal block means).
  double lag1 = 0;
  /// stderr_ corrected for a correlation between neighbouring blocks (blocks shorter than the
  /// series' correlation time): stderr_ sqrt((1 + r) / (1 - r)), r = lag1 clipped to [0, 0.9]
  /// (the AR(1) variance of a mean; never smaller than stderr_).
  double stderr_corrected = 0;
  std::size_t blocks = 0;   ///< B used
  std::size_t samples = 0;  ///< samples used: B times the block length
};

/// @brief The means of B equal contiguous blocks of @p series, B = min(@p blocks, size) (at
/// least 1); the first size % B samples are dropped so that the blocks end at the last sample
/// (the end of a run is the part nearest to steady state). Empty for an empty series.
/// @param series samples (any unit); @param blocks B requested.
std::vector<double> block_means(const std::vector<double>& series, std::size_t blocks);

/// @brief Mean and errors from B block means taken as one sample each (Flyvbjerg and Petersen
/// 1989): stderr_ = sd / sqrt(B), corrected by the lag-1 autocorrelation r of the block means
/// (clipped to [0, 0.9]) to the AR(1) value stderr_ sqrt((1 + r) / (1 - r)).
/// @param means the B block means; @param samples the samples they hold (reported only).
BlockMean block_mean_of(const std::vector<double>& means, std::size_t samples);

/// @brief block_mean_of(block_means(series, blocks)): mean and standard errors of a correlated
/// series from @p blocks equal blocks, the first size % B samples dropped. An empty series
/// gives NaN mean and errors and 0 blocks.
/// @param series samples after the steady-state start; @param blocks B >= 2 requested.
BlockMean block_mean(const std::vector<double>& series, std::size_t blocks);

/// Mean over independent beds and its standard error (pooled_mean()).
struct PooledMean {
  double mean = 0;     ///< plain mean of the bed means
  double error = 0;    ///< max(between, within) of those that are finite; NaN if neither is
  double between = 0;  ///< sd(bed means, n - 1) / sqrt(N); NaN for one bed
  double within = 0;   ///< sqrt(sum e_i^2) / N from the beds' own errors; NaN without errors
  std::size_t beds = 0;
};

/// @brief Mean of N independent beds (replicas, seeds) of one scene, with its error.
///
/// The plain mean of the bed means: every bed is an equally valid sample of how a bed can be
/// packed, and the packing spread exceeds a bed's time-average error (docs/crosscheck.md), so
/// inverse-variance weights would favour beds by their length. Its error is the larger of the
/// between-bed error (the scatter of the means, which holds the packing spread and each bed's
/// time-average noise: unbiased, but itself uncertain from 2 or 3 beds) and the within-bed
/// error (the floor the beds' own errors set). Adding the two in quadrature would count the
/// time-average noise twice. One bed: its value, between NaN, error its own error (a lower
/// bound: the packing spread is unknown).
/// @param means the N bed means; @param errors their standard errors (same length), or empty
/// when the beds carry none (then error = between). Throws std::invalid_argument when the
/// lengths differ.
PooledMean pooled_mean(const std::vector<double>& means, const std::vector<double>& errors = {});

/// Observed orders that richardson() accepts: below, the differences barely shrink (not in the
/// asymptotic range); above, the last difference is small by cancellation rather than by
/// convergence (a Q2-Q1 force converges at order 1 to 3), and the correction would be too small.
inline constexpr double kRichardsonMinOrder = 0.5, kRichardsonMaxOrder = 3.0;

/// Richardson extrapolation of three mesh levels (richardson()).
struct Richardson {
  double order = 0;       ///< observed order p; NaN when the differences are 0 or change sign
  double limit = 0;       ///< extrapolated value if accepted, else the finest value
  double error = 0;       ///< |limit - f3| if accepted, else the last change |f3 - f2|
  bool accepted = false;  ///< whether the levels passed the acceptance test
};

/// @brief Observed order and limit of a quantity f = f_inf + C h^p computed on three meshes.
///
/// With r = h1 / h2 = h2 / h3, e1 = f2 - f1, e2 = f3 - f2: p = ln(e1 / e2) / ln r and
/// f_inf = f3 + e2 / (r^p - 1). Acceptance test: e1 and e2 non-zero with the same sign
/// (monotone) and min_order <= p <= max_order. Accepted: limit f_inf, error the last
/// correction |f_inf - f3|. Otherwise the levels are not in the asymptotic range: limit f3,
/// error the last change |f3 - f2|, never an extrapolation with an order the data do not show.
/// @param h cell sizes h1 > h2 > h3 > 0 (m) with a constant ratio (to 1e-9 relative);
/// @param values f1, f2, f3 on them. Throws std::invalid_argument otherwise.
Richardson richardson(const std::vector<double>& h, const std::vector<double>& values,
                      double min_order = kRichardsonMinOrder,
                      double max_order = kRichardsonMaxOrder);

}  // namespace grainlift
