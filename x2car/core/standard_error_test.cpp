#include "x2car/core/standard_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace x2car {
namespace {

// An AR(1) series x_k = phi x_(k-1) + e_k at 10 Hz, started from its stationary distribution
// (variance 1).
struct Ar1Series {
  std::vector<double> times, values;
};

Ar1Series ar1_series(std::size_t n, double phi, std::mt19937_64& generator) {
  std::normal_distribution<double> normal;
  Ar1Series series;
  const double innovation = std::sqrt(1.0 - phi * phi);
  double x = normal(generator);
  for (std::size_t k = 0; k < n; ++k) {
    series.times.push_back(0.1 * static_cast<double>(k));
    series.values.push_back(x);
    x = phi * x + innovation * normal(generator);
  }
  return series;
}

// The exact variance of the mean of n samples of that series: (1 + 2 sum (1 - k/n) phi^k) / n.
double ar1_variance_of_mean(std::size_t n, double phi) {
  double sum = 1.0;
  double power = 1.0;
  for (std::size_t k = 1; k < n; ++k) {
    power *= phi;
    sum += 2.0 * (1.0 - static_cast<double>(k) / static_cast<double>(n)) * power;
  }
  return sum / static_cast<double>(n);
}

double mean_of(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

TEST(SmallSampleFactor, IsTheStudentTQuantileOverTheNormalOne) {
  EXPECT_NEAR(small_sample_factor(1.0), 12.7062 / 1.95996, 1e-3);
  EXPECT_NEAR(small_sample_factor(2.0), 4.3027 / 1.95996, 1e-3);
  EXPECT_NEAR(small_sample_factor(5.0), 2.5706 / 1.95996, 1e-3);
  EXPECT_NEAR(small_sample_factor(10.0), 2.2281 / 1.95996, 1e-3);
  EXPECT_NEAR(small_sample_factor(60.0), 2.0003 / 1.95996, 1e-3);
  EXPECT_NEAR(small_sample_factor(1e6), 1.0, 1e-4);
  // Between the integers, and decreasing.
  EXPECT_LT(small_sample_factor(2.5), small_sample_factor(2.0));
  EXPECT_GT(small_sample_factor(2.5), small_sample_factor(3.0));
  EXPECT_THROW(small_sample_factor(0.5), std::invalid_argument);
}

TEST(MovingBlockStandardError, MatchesTheVarianceOfTheMeanOfAnAr1Series) {
  // phi = 0.9 at 10 Hz: correlated over about a second; 10 s blocks, 300 s series. The samples'
  // own s / sqrt(n) would be sqrt(19) = 4.4 times too small.
  constexpr std::size_t kSamples = 3000;
  constexpr double kPhi = 0.9;
  std::mt19937_64 generator(11);
  double sum_variance = 0.0;
  constexpr int kSeries = 200;
  for (int s = 0; s < kSeries; ++s) {
    const Ar1Series series = ar1_series(kSamples, kPhi, generator);
    const MovingBlockStandardError se =
        moving_block_standard_error(series.times, series.values, {.block_s = 10.0});
    EXPECT_EQ(se.block_samples, 100.0);
    EXPECT_NEAR(se.degrees_of_freedom, 1.5 * 29.0, 1e-9);
    sum_variance += se.standard_error * se.standard_error;
  }
  // The block estimate is biased low by about (1/L) sum_k |k| rho_k / sum_k rho_k = 9.5 % here.
  const double ratio = sum_variance / kSeries / ar1_variance_of_mean(kSamples, kPhi);
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.05);
}

TEST(MovingBlockStandardError, IsUnbiasedForIndependentSamples) {
  constexpr std::size_t kSamples = 500;
  std::mt19937_64 generator(12);
  double sum_variance = 0.0;
  constexpr int kSeries = 400;
  for (int s = 0; s < kSeries; ++s) {
    const Ar1Series series = ar1_series(kSamples, 0.0, generator);
    sum_variance += std::pow(
        moving_block_standard_error(series.times, series.values, {.block_s = 5.0}).standard_error,
        2.0);
  }
  EXPECT_NEAR(sum_variance / kSeries * kSamples, 1.0, 0.1);
}

TEST(MovingBlockStandardError, WithTheSmallSampleFactorCoversAShortSeries) {
  // 25 s of an AR(1) correlated over ~1 s, 10 s blocks: 2.5 blocks, 2.25 degrees of freedom. The
  // corrected +-1.96 SE interval should hold the true mean (0) about 95 % of the time; the plain
  // one would not.
  constexpr std::size_t kSamples = 250;
  std::mt19937_64 generator(13);
  int covered = 0, covered_plain = 0;
  constexpr int kSeries = 1000;
  for (int s = 0; s < kSeries; ++s) {
    const Ar1Series series = ar1_series(kSamples, 0.9, generator);
    const MovingBlockStandardError se =
        moving_block_standard_error(series.times, series.values, {.block_s = 10.0});
    ASSERT_GE(se.degrees_of_freedom, 1.0);
    const double error = std::abs(mean_of(series.values));
    covered += error <= 1.96 * small_sample_factor(se.degrees_of_freedom) * se.standard_error;
    covered_plain += error <= 1.96 * se.standard_error;
  }
  EXPECT_GT(covered, 0.91 * kSeries);
  EXPECT_LT(covered, 0.99 * kSeries);
  EXPECT_LT(covered_plain, covered - 0.05 * kSeries);
}

TEST(MovingBlockStandardError, CutsASeriesShorterThanTwoBlocksInTwo) {
  std::vector<double> times, values;
  for (int i = 0; i < 10; ++i) {
    times.push_back(i);
    values.push_back(i < 5 ? 0.0 : 1.0);
  }
  const MovingBlockStandardError se = moving_block_standard_error(times, values, {.block_s = 60.0});
  EXPECT_EQ(se.block_samples, 5.0);
  EXPECT_DOUBLE_EQ(se.degrees_of_freedom, 1.5);
  // Blocks of 5 starting at 0..5: means 0, .2, .4, .6, .8, 1 about 0.5; 5 / (6 * 5) * 0.7.
  EXPECT_NEAR(se.standard_error, std::sqrt(5.0 / 30.0 * 0.7), 1e-12);
}

TEST(MovingBlockStandardError, FallsBackToIndependentSamplesBelowFourSamples) {
  const std::vector<double> times{0.0, 1.0, 2.0};
  const std::vector<double> values{1.0, 2.0, 3.0};
  const MovingBlockStandardError se = moving_block_standard_error(times, values, {.block_s = 3.0});
  EXPECT_EQ(se.degrees_of_freedom, 0.0);
  EXPECT_NEAR(se.standard_error, 1.0 / std::sqrt(3.0), 1e-12);
  EXPECT_THROW(moving_block_standard_error(std::vector<double>{0.0}, std::vector<double>{1.0}),
               std::invalid_argument);
  EXPECT_THROW(moving_block_standard_error(times, values, {.block_s = 0.0}), std::invalid_argument);
}

TEST(SeriesStandardError, IsTheLargerOfBlocksAndFormalWithTheFloorInQuadrature) {
  std::mt19937_64 generator(14);
  const Ar1Series series = ar1_series(600, 0.9, generator);
  const SeriesStandardError se = series_standard_error(series.times, series.values, {}, 0.05);
  const MovingBlockStandardError blocks = moving_block_standard_error(series.times, series.values);
  EXPECT_DOUBLE_EQ(se.block,
                   small_sample_factor(blocks.degrees_of_freedom) * blocks.standard_error);
  // Correlated samples: the blocks see more than the formal error.
  EXPECT_GT(se.block, 2.0 * se.formal);
  EXPECT_DOUBLE_EQ(se.combined, std::hypot(se.block, 0.05));
  EXPECT_THROW(series_standard_error(series.times, series.values, {}, -1.0), std::invalid_argument);
}

TEST(CombinedStandardError, TakesTheLargestPartAndAddsTheFloorInQuadrature) {
  const std::vector<double> parts{0.3, 0.4, 0.1};
  EXPECT_DOUBLE_EQ(combined_standard_error(parts), 0.4);
  EXPECT_DOUBLE_EQ(combined_standard_error(parts, 0.3), 0.5);
  EXPECT_DOUBLE_EQ(combined_standard_error({}, 0.2), 0.2);
}

}  // namespace
}  // namespace x2car
