// The statistics module (statistics.h): block means recover the standard error of the mean of
// independent and of correlated (AR(1)) series, pooling over beds gives the error of a mean of
// beds, Richardson extrapolation recovers the order and limit of a synthetic convergence.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "grainlift/shared/statistics/statistics.h"

using namespace grainlift;

namespace {
/// A stationary AR(1) series x_{i+1} = phi x_i + e_i, e_i ~ N(0, 1).
std::vector<double> ar1(std::size_t n, double phi, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double v = g(rng) / std::sqrt(1 - phi * phi);  // stationary start
  for (auto& xi : x) xi = v = phi * v + g(rng);
  return x;
}

/// The exact standard deviation of the mean of n samples of that AR(1) series:
/// Var = Var(x) / n [1 + 2 sum_{k=1}^{n-1} (1 - k/n) phi^k], Var(x) = 1 / (1 - phi^2).
double ar1_mean_sd(std::size_t n, double phi) {
  double s = 0, pk = 1;
  for (std::size_t k = 1; k < n; ++k) s += (1 - double(k) / double(n)) * (pk *= phi);
  return std::sqrt(1 / (1 - phi * phi) / double(n) * (1 + 2 * s));
}
}  // namespace

TEST(BlockMean, StandardErrorOfIndependentSamples) {
  // For independent N(5, 2^2) samples, the block standard error estimates 2 / sqrt(n);
  // with 40 blocks the estimate itself scatters by about 1 / sqrt(2 * 39) = 11 %: allow 35 %.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(5.0, 2.0);
  std::vector<double> x(40000);
  for (auto& v : x) v = g(rng);
  const BlockMean m = block_mean(x, 40);
  EXPECT_EQ(m.blocks, 40u);
  EXPECT_EQ(m.samples, 40000u);
  EXPECT_NEAR(m.mean, 5.0, 4 * 2.0 / std::sqrt(40000.0));
  EXPECT_NEAR(m.stderr_, 2.0 / std::sqrt(40000.0), 0.35 * 2.0 / std::sqrt(40000.0));
}

TEST(BlockMean, DropsTheOldestRemainderAndHandlesShortSeries) {
  // 10 samples in 3 blocks: the first sample is dropped, blocks of 3 end at the last sample.
  std::vector<double> x{100, 1, 1, 1, 2, 2, 2, 3, 3, 3};
  const BlockMean m = block_mean(x, 3);
  EXPECT_DOUBLE_EQ(m.mean, 2.0);
  EXPECT_EQ(m.samples, 9u);
  EXPECT_NEAR(m.stderr_, std::sqrt(1.0 / 3.0), 1e-12);  // sd of {1,2,3} = 1, / sqrt(3)
  const BlockMean one = block_mean({4.0}, 10);
  EXPECT_DOUBLE_EQ(one.mean, 4.0);
  EXPECT_EQ(one.blocks, 1u);
  EXPECT_TRUE(std::isnan(one.stderr_));
  EXPECT_TRUE(std::isnan(one.stderr_corrected));
  const BlockMean none = block_mean({}, 10);
  EXPECT_EQ(none.blocks, 0u);
  EXPECT_TRUE(std::isnan(none.mean) && std::isnan(none.stderr_corrected));
}

TEST(BlockMean, CorrectedErrorOfAnAr1SeriesMatchesTheAnalyticVarianceOfItsMean) {
  // AR(1) with phi = 0.99: integrated correlation time (1 + phi) / (1 - phi) = 199 samples.
  // 20000 samples in 100 blocks of 200, blocks about one correlation time long: neighbouring
  // block means are correlated (lag-1 ~ 0.4) and the plain block error is about 25 % too
  // small. Over 200 series, the root-mean-square corrected error is within 20 % of the exact
  // sd of the mean (the estimate scatters by ~10 % per series and r's clip at 0 biases it a
  // little high), the plain one more than 15 % below it; the scatter of the 200 means
  // themselves checks the analytic formula to 15 % (its own sampling error is 5 %).
  const double phi = 0.99;
  const std::size_t n = 20000, B = 100;
  const double truth = ar1_mean_sd(n, phi);
  std::mt19937_64 rng(11);
  double plain2 = 0, corrected2 = 0, means2 = 0;
  const int series = 200;
  for (int s = 0; s < series; ++s) {
    const BlockMean m = block_mean(ar1(n, phi, rng), B);
    EXPECT_GE(m.stderr_corrected, m.stderr_);
    plain2 += m.stderr_ * m.stderr_ / series;
    corrected2 += m.stderr_corrected * m.stderr_corrected / series;
    means2 += m.mean * m.mean / series;
  }
  EXPECT_NEAR(std::sqrt(means2), truth, 0.15 * truth);
  EXPECT_LT(std::sqrt(plain2), 0.85 * truth);
  EXPECT_NEAR(std::sqrt(corrected2), truth, 0.2 * truth);
}

TEST(BlockMean, NoCorrectionForIndependentBlocks) {
  // White noise: lag-1 correlation of block means ~ N(0, 1/B); the correction stays near 1:
  // within 40 % for 40 blocks.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(40000);
  for (auto& v : x) v = g(rng);
  const BlockMean m = block_mean(x, 40);
  EXPECT_LT(std::abs(m.lag1), 0.4);
  EXPECT_LT(m.stderr_corrected, 1.4 * m.stderr_);
}

TEST(BlockMean, BlockMeansAndTheirSummaryComposeToBlockMean) {
  std::mt19937_64 rng(2);
  const std::vector<double> x = ar1(1003, 0.9, rng);
  const std::vector<double> means = block_means(x, 10);
  ASSERT_EQ(means.size(), 10u);
  const BlockMean a = block_mean(x, 10), b = block_mean_of(means, 1000);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.stderr_corrected, b.stderr_corrected);
  EXPECT_EQ(a.samples, 1000u);
}

TEST(PooledMean, ErrorOfTheMeanOfBedsWithAPackingSpread) {
  // Beds whose means scatter by a packing spread s = 3 around 10, each with its own block
  // error e = 1: the mean of N = 40 beds has sd sqrt(s^2 + e^2) / sqrt(N) = 0.5; the pooled
  // error estimates it (between dominates) within 30 % (its scatter is 1 / sqrt(78) = 11 %).
  std::mt19937_64 rng(17);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::size_t N = 40;
  std::vector<double> means, errors(N, 1.0);
  for (std::size_t i = 0; i < N; ++i) means.push_back(10 + 3 * g(rng) + g(rng));
  const PooledMean p = pooled_mean(means, errors);
  const double truth = std::sqrt(10.0 / double(N));
  EXPECT_EQ(p.beds, N);
  EXPECT_NEAR(p.mean, 10.0, 4 * truth);
  EXPECT_NEAR(p.within, 1.0 / std::sqrt(double(N)), 1e-12);
  EXPECT_EQ(p.error, p.between);
  EXPECT_NEAR(p.error, truth, 0.3 * truth);
}

TEST(PooledMean, BedsThatDifferByTheirNoiseOnlyKeepTheirOwnErrorAsAFloor) {
  // Three beds agreeing by chance far better than their errors of 0.3: between is tiny, the
  // error is the within-bed one 0.3 sqrt(3) / 3.
  const PooledMean p = pooled_mean({2.00, 2.01, 1.99}, {0.3, 0.3, 0.3});
  EXPECT_DOUBLE_EQ(p.mean, 2.0);
  EXPECT_NEAR(p.between, 0.01 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(p.error, 0.3 / std::sqrt(3.0), 1e-12);
}

TEST(PooledMean, OneBedAndBedsWithoutErrors) {
  const PooledMean one = pooled_mean({4.0}, {0.5});
  EXPECT_EQ(one.mean, 4.0);
  EXPECT_TRUE(std::isnan(one.between));
  EXPECT_EQ(one.error, 0.5);  // its own error: a lower bound, the packing spread unknown
  const PooledMean bare = pooled_mean({1.0, 3.0});
  EXPECT_EQ(bare.mean, 2.0);
  EXPECT_TRUE(std::isnan(bare.within));
  EXPECT_NEAR(bare.error, 1.0, 1e-12);  // sd sqrt(2) / sqrt(2)
  EXPECT_TRUE(std::isnan(pooled_mean({7.0}).error));
  EXPECT_THROW(pooled_mean({1.0, 2.0}, {0.1}), std::invalid_argument);
}

TEST(Richardson, RecoversTheLimitAndOrderOfAPowerLaw) {
  // f = 1.5 + 0.7 h^1.5 on h = 0.4, 0.2, 0.1: order 1.5 and limit 1.5 to rounding.
  auto f = [](double h) { return 1.5 + 0.7 * std::pow(h, 1.5); };
  const Richardson r = richardson({0.4, 0.2, 0.1}, {f(0.4), f(0.2), f(0.1)});
  EXPECT_TRUE(r.accepted);
  EXPECT_NEAR(r.order, 1.5, 1e-10);
  EXPECT_NEAR(r.limit, 1.5, 1e-12);
  // ratio 3: the same
  const Richardson r3 = richardson({0.9, 0.3, 0.1}, {f(0.9), f(0.3), f(0.1)});
  EXPECT_NEAR(r3.order, 1.5, 1e-10);
  EXPECT_NEAR(r3.limit, 1.5, 1e-12);
}

TEST(Richardson, ErrorCoversAHigherOrderTerm) {
  // f = 1 + h^2 + h^3: observed order 2.25 on h = 0.4, 0.2, 0.1, limit 1.0012 against 1: the
  // quoted error (the last correction, 0.0098) covers the true error 0.0012.
  auto f = [](double h) { return 1 + h * h + h * h * h; };
  const Richardson r = richardson({0.4, 0.2, 0.1}, {f(0.4), f(0.2), f(0.1)});
  EXPECT_TRUE(r.accepted);
  EXPECT_NEAR(r.order, 2.0, 0.3);
  EXPECT_LT(std::abs(r.limit - 1.0), r.error);
  EXPECT_LT(std::abs(r.limit - 1.0), std::abs(f(0.1) - 1.0) / 5);  // better than the finest
}

TEST(Richardson, RefusesLevelsOutsideTheAsymptoticRange) {
  // not monotone: no order, the finest value with the last change as its error
  const Richardson a = richardson({0.4, 0.2, 0.1}, {1.0, 2.0, 1.5});
  EXPECT_FALSE(a.accepted);
  EXPECT_TRUE(std::isnan(a.order));
  EXPECT_EQ(a.limit, 1.5);
  EXPECT_EQ(a.error, 0.5);
  // order 4 (above 3) and order 0.2 (below 0.5): refused, order reported
  const Richardson b = richardson({0.4, 0.2, 0.1}, {1 + 0.0256, 1 + 0.0016, 1 + 0.0001});
  EXPECT_FALSE(b.accepted);
  EXPECT_NEAR(b.order, 4.0, 1e-9);
  EXPECT_EQ(b.limit, 1 + 0.0001);
  const Richardson c = richardson(
      {0.4, 0.2, 0.1}, {std::pow(0.4, 0.2), std::pow(0.2, 0.2), std::pow(0.1, 0.2)});
  EXPECT_FALSE(c.accepted);
  EXPECT_NEAR(c.order, 0.2, 1e-9);
  EXPECT_THROW(richardson({0.4, 0.2, 0.05}, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(richardson({0.1, 0.2, 0.4}, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(richardson({0.4, 0.2}, {1, 2}), std::invalid_argument);
}
