#include "x2car/core/prior_slope.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "x2car/core/robust_stats.hpp"

namespace x2car {
namespace {

struct Samples {
  std::vector<double> times, values, regressor;
  std::vector<bool> use;
};

// 10 Hz samples v = offset + slope * x + white noise, with x a sine of the given mean and swing
// over a 30 s period (a car braking and speeding up about a mean acceleration).
Samples samples(std::size_t n, double offset, double slope, double mean_x, double swing_x,
                double noise, std::uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::normal_distribution<double> normal(0.0, noise);
  Samples s;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 0.1 * static_cast<double>(i);
    const double x = mean_x + swing_x * std::sin(2.0 * M_PI * t / 30.0);
    s.times.push_back(t);
    s.regressor.push_back(x);
    s.values.push_back(offset + slope * x + normal(generator));
    s.use.push_back(true);
  }
  return s;
}

TEST(OffsetWithPriorSlope, DataThatVaryFindTheSlopeAndTheOffsetDespiteAWrongPrior) {
  const Samples s = samples(600, 0.05, 0.007, 0.2, 1.5, 0.001, 3);
  const OffsetWithSlope fit =
      offset_with_prior_slope(s.times, s.values, s.regressor, s.use,
                              {.mean = 0.005, .standard_deviation = 0.003}, {.block_s = 5.0});
  EXPECT_NEAR(fit.slope, 0.007, 1e-4);
  EXPECT_NEAR(fit.offset, 0.05, 1e-4);
  EXPECT_LT(fit.slope_std, 3e-4);  // the data, not the prior, decide
  EXPECT_GE(fit.standard_error, fit.noise_standard_error);
}

TEST(OffsetWithPriorSlope, AConstantRegressorLeavesTheSlopeToThePriorAndItsSpreadToTheError) {
  // Speeding up at 1 m/s^2 all along: the data cannot tell the slope from the offset.
  const Samples s = samples(250, 0.05, 0.007, 1.0, 0.0, 0.001, 4);
  const SlopePrior prior{.mean = 0.005, .standard_deviation = 0.003};
  const OffsetWithSlope fit =
      offset_with_prior_slope(s.times, s.values, s.regressor, s.use, prior, {.block_s = 5.0});
  EXPECT_DOUBLE_EQ(fit.slope, prior.mean);
  EXPECT_DOUBLE_EQ(fit.slope_std, prior.standard_deviation);
  // offset = mean(v) - 0.005 = 0.05 + 0.002: the error the prior's spread must cover.
  EXPECT_NEAR(fit.offset, 0.052, 3e-4);
  EXPECT_NEAR(fit.standard_error, 0.003, 2e-4);
  EXPECT_GT(fit.standard_error, std::abs(fit.offset - 0.05));
}

TEST(OffsetWithPriorSlope, CoversTheTruthOverManyNoisyRuns) {
  // Short, correlated-free runs with a slope the prior gets only roughly: |error| <= 2 SE in at
  // least 90 % of them, and the SE not several times the typical error.
  int covered = 0;
  std::vector<double> errors, standard_errors;
  constexpr int kRuns = 200;
  for (int run = 0; run < kRuns; ++run) {
    const Samples s = samples(250, -0.02, 0.006, 0.3 * (run % 3), 0.8, 0.002,
                              100 + static_cast<std::uint64_t>(run));
    const OffsetWithSlope fit =
        offset_with_prior_slope(s.times, s.values, s.regressor, s.use,
                                {.mean = 0.005, .standard_deviation = 0.0025}, {.block_s = 2.0});
    const double error = std::abs(fit.offset + 0.02);
    covered += error <= 2.0 * fit.standard_error ? 1 : 0;
    errors.push_back(error);
    standard_errors.push_back(fit.standard_error);
  }
  EXPECT_GE(covered, 180);
  EXPECT_LE(median(standard_errors), 3.0 * median(errors));
}

TEST(OffsetWithPriorSlope, LeavesOutTheUnusedSamplesAndAddsTheFloor) {
  Samples s = samples(300, 0.05, 0.007, 0.0, 1.0, 0.001, 5);
  s.values[10] = 5.0;  // an outlier the caller masked
  s.use[10] = false;
  const SlopePrior prior{.mean = 0.007, .standard_deviation = 0.003};
  const OffsetWithSlope fit =
      offset_with_prior_slope(s.times, s.values, s.regressor, s.use, prior, {.block_s = 5.0});
  EXPECT_NEAR(fit.offset, 0.05, 2e-4);
  const OffsetWithSlope floored =
      offset_with_prior_slope(s.times, s.values, s.regressor, s.use, prior, {.block_s = 5.0}, 0.01);
  EXPECT_NEAR(floored.standard_error, std::hypot(fit.standard_error, 0.01), 1e-12);
}

TEST(OffsetWithPriorSlope, RejectsBadArguments) {
  const Samples s = samples(10, 0.0, 0.0, 0.0, 1.0, 0.001, 6);
  const MovingBlockOptions blocks{.block_s = 1.0};
  EXPECT_THROW(offset_with_prior_slope(s.times, s.values, s.regressor, s.use,
                                       {.mean = 0.0, .standard_deviation = 0.0}, blocks),
               std::invalid_argument);
  EXPECT_THROW(offset_with_prior_slope(s.times, s.values, s.regressor, std::vector<bool>(10, false),
                                       {.mean = 0.0, .standard_deviation = 1.0}, blocks),
               std::invalid_argument);
  EXPECT_THROW(offset_with_prior_slope(s.times, s.values, s.regressor, s.use,
                                       {.mean = 0.0, .standard_deviation = 1.0}, blocks, -1.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace x2car
