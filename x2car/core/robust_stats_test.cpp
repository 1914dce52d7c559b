#include "x2car/core/robust_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

TEST(Median, OddAndEvenCounts) {
  const std::vector<double> odd = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(median(odd), 3.0);
  const std::vector<double> even = {7, 1, 3, 5};
  EXPECT_DOUBLE_EQ(median(even), 4.0);
  EXPECT_THROW(median({}), std::invalid_argument);
}

TEST(MedianAbsoluteDeviation, HandComputed) {
  // median 3; |deviations| = 2 1 0 1 97 -> sorted 0 1 1 2 97 -> MAD 1
  const std::vector<double> values = {1, 2, 3, 4, 100};
  EXPECT_DOUBLE_EQ(median_absolute_deviation(values), 1.0);
  EXPECT_DOUBLE_EQ(robust_sigma(values), kMadToSigma);
}

TEST(MadInlierMask, RejectsTheOutlierOnly) {
  const std::vector<double> values = {1, 2, 3, 4, 100};
  // limit = 3 * 1.4826 * 1 = 4.45 around the median 3: 100 is out, the rest are in.
  const std::vector<bool> inliers = mad_inlier_mask(values, {.k = 3.0});
  EXPECT_EQ(inliers, (std::vector<bool>{true, true, true, true, false}));
  // A tighter k = 0.6 gives limit 0.89: only the median itself survives.
  EXPECT_EQ(mad_inlier_mask(values, {.k = 0.6}),
            (std::vector<bool>{false, false, true, false, false}));
}

TEST(MadInlierMask, MinSigmaGuardsAgainstZeroMad) {
  const std::vector<double> values = {2, 2, 2, 2, 2.01};
  EXPECT_EQ(mad_inlier_mask(values, {.k = 3.0})[4], false);  // MAD = 0: any difference is out
  EXPECT_EQ(mad_inlier_mask(values, {.k = 3.0, .min_sigma = 0.01})[4], true);
  EXPECT_THROW(mad_inlier_mask(values, {.k = 0.0}), std::invalid_argument);
}

TEST(WeightedMean, HandComputed) {
  const std::vector<double> values = {1, 2, 4};
  EXPECT_DOUBLE_EQ(weighted_mean(values), 7.0 / 3.0);
  const std::vector<double> weights = {1, 1, 2};
  EXPECT_DOUBLE_EQ(weighted_mean(values, weights), (1 + 2 + 8) / 4.0);
  const std::vector<double> zero = {0, 0, 0};
  EXPECT_THROW(weighted_mean(values, zero), std::invalid_argument);
  const std::vector<double> negative = {1, -1, 1};
  EXPECT_THROW(weighted_mean(values, negative), std::invalid_argument);
}

TEST(StandardDeviation, HandComputed) {
  // mean 5, squared deviations 9 1 1 9 -> sum 20 / (4 - 1)
  const std::vector<double> values = {2, 4, 6, 8};
  EXPECT_DOUBLE_EQ(standard_deviation(values), std::sqrt(20.0 / 3.0));
  const std::vector<double> one = {1};
  EXPECT_THROW(standard_deviation(one), std::invalid_argument);
}

TEST(StandardError, EqualWeightsGiveSOverRootN) {
  const std::vector<double> estimates = {2, 4, 6, 8};
  EXPECT_NEAR(standard_error_of_weighted_mean(estimates), std::sqrt(20.0 / 3.0) / 2.0, 1e-15);
}

TEST(StandardError, HandComputedWithWeights) {
  // weights 1 3 -> normalised 0.25 0.75, mean 0.25*0 + 0.75*4 = 3,
  // SE^2 = 2/1 * (0.0625 * 9 + 0.5625 * 1) = 2.25
  const std::vector<double> estimates = {0, 4};
  const std::vector<double> weights = {1, 3};
  EXPECT_NEAR(standard_error_of_weighted_mean(estimates, weights), 1.5, 1e-15);
}

TEST(Bootstrap, MatchesTheAnalyticStandardErrorOfTheMean) {
  std::mt19937_64 generator(7);
  std::normal_distribution<double> noise(0.0, 2.0);
  std::vector<double> values(400);
  for (double& value : values) value = noise(generator);
  const auto mean = [](std::span<const double> v, std::span<const double> w) {
    return weighted_mean(v, w);
  };
  const double bootstrap =
      bootstrap_standard_error(values, {}, mean, {.resamples = 2000, .seed = 3});
  const double analytic = standard_deviation(values) / std::sqrt(400.0);
  // 2000 resamples estimate the SE to about 1/sqrt(2 * 2000) = 1.6 %; allow 8 %.
  EXPECT_NEAR(bootstrap / analytic, 1.0, 0.08);
  // Seeded: the same seed gives the same number, another seed a different one.
  EXPECT_EQ(bootstrap, bootstrap_standard_error(values, {}, mean, {.resamples = 2000, .seed = 3}));
  EXPECT_NE(bootstrap, bootstrap_standard_error(values, {}, mean, {.resamples = 2000, .seed = 4}));
}

TEST(Bootstrap, WorksWithCircularStatisticsAndWeights) {
  const std::vector<double> headings = {rad_from_deg(179.5), rad_from_deg(-179.7),
                                        rad_from_deg(179.9), rad_from_deg(-179.2)};
  const std::vector<double> weights = {1, 2, 1, 3};
  const auto mean_heading = [](std::span<const double> v, std::span<const double> w) {
    return circular_mean(v, w);
  };
  // The spread is under a degree; measured linearly across the seam it would be about 180 deg.
  const double error = bootstrap_standard_error(headings, weights, mean_heading,
                                                {.resamples = 500, .circular = true});
  EXPECT_GT(error, 0.0);
  EXPECT_LT(error, rad_from_deg(1.0));
  EXPECT_GT(bootstrap_standard_error(headings, weights, mean_heading, {.resamples = 500}), 1.0);
}

}  // namespace
}  // namespace x2car
