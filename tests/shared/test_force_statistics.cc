// Drag and lift follow docs/conventions.md: D = -F.V/|V|, L = F.(z x V/|V|); block averages give the
// right standard error for independent samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "grainlift/shared/force_statistics.h"

using namespace grainlift;

TEST(DragLift, SignConventionsOfTargets) {
  // V along +x: a force opposing motion (-x) is positive drag; lift is F_y.
  auto r = project_drag_lift(-3.0, 2.0, 0.5, 0.0);
  EXPECT_DOUBLE_EQ(r.drag, 3.0);
  EXPECT_DOUBLE_EQ(r.lift, 2.0);
  // V along -x: z x V/|V| = -y, so a force along +y is negative lift; +x opposes motion.
  r = project_drag_lift(3.0, 2.0, -0.5, 0.0);
  EXPECT_DOUBLE_EQ(r.drag, 3.0);
  EXPECT_DOUBLE_EQ(r.lift, -2.0);
  // V along +y: z x y = -x, so a force along -x is positive lift.
  r = project_drag_lift(-1.0, -4.0, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(r.drag, 4.0);
  EXPECT_DOUBLE_EQ(r.lift, 1.0);
  // Inverse Magnus (Kumar 2019): omega > 0 (ccw), V along +x, lift along -omega x V = -y.
  // -omega z x V x = -omega V y: a force along -y is negative lift under our convention.
  r = project_drag_lift(0.0, -1.0, 1.0, 0.0);
  EXPECT_LT(r.lift, 0.0);
  EXPECT_THROW(project_drag_lift(1, 1, 0, 0), std::invalid_argument);
}

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
  EXPECT_NEAR(m.stderr_, std::sqrt(1.0 / 3.0), 1e-12);  // sd of {1,2,3} = 1, / sqrt(3)
  const BlockMean one = block_mean({4.0}, 10);
  EXPECT_DOUBLE_EQ(one.mean, 4.0);
  EXPECT_TRUE(std::isnan(one.stderr_));
}

TEST(BlockMean, CorrelationCorrectionRestoresTheErrorOfShortBlocks) {
  // An AR(1) series x_{i+1} = a x_i + e with a = 0.999 (correlation time 1000 samples) in 40
  // blocks of 250 samples: neighbouring block means are correlated, the plain block error is
  // too small. The true standard error of the mean of n samples is
  // sigma_e / (1 - a) / sqrt(n) (long-series limit). Over 200 series: the corrected error's
  // mean is within 30% of it, the plain one more than 30% below it.
  const double a = 0.999, sigma_e = 1.0;
  const std::size_t n = 10000;
  const double truth = sigma_e / (1 - a) / std::sqrt(double(n));
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, sigma_e);
  double plain = 0, corrected = 0;
  const int series = 200;
  for (int s = 0; s < series; ++s) {
    std::vector<double> x(n);
    double v = g(rng) / std::sqrt(1 - a * a);  // stationary start
    for (auto& xi : x) xi = v = a * v + g(rng);
    const BlockMean m = block_mean(x, 40);
    EXPECT_GE(m.stderr_corrected, m.stderr_);
    plain += m.stderr_ / series;
    corrected += m.stderr_corrected / series;
  }
  EXPECT_LT(plain, 0.7 * truth);
  EXPECT_NEAR(corrected, truth, 0.3 * truth);
}

TEST(BlockMean, NoCorrectionForIndependentBlocks) {
  // White noise: lag-1 correlation of block means ~ N(0, 1/B); the correction stays within
  // the clip sqrt(1.9/0.1) only in theory, in practice near 1: within 40% for 40 blocks.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(40000);
  for (auto& v : x) v = g(rng);
  const BlockMean m = block_mean(x, 40);
  EXPECT_LT(std::abs(m.lag1), 0.4);
  EXPECT_LT(m.stderr_corrected, 1.4 * m.stderr_);
}
