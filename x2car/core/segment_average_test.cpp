#include "x2car/core/segment_average.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "x2car/core/test_matchers.hpp"

namespace x2car {
namespace {

using testing::AngleNearDeg;

// n_segments runs of 20 s at 10 Hz separated by 5 s of rejected samples; each sample is
// truth + N(0, noise) + a per-segment offset drawn with sigma segment_sigma.
struct Samples {
  std::vector<double> times, angles;
  Segmentation segmentation;
};

Samples make_samples(double truth, int n_segments, double noise, double segment_sigma,
                     unsigned seed) {
  std::mt19937_64 generator(seed);
  std::normal_distribution<double> normal;
  Samples samples;
  for (int s = 0; s < n_segments; ++s) {
    const double segment_offset = segment_sigma * normal(generator);
    for (int i = 0; i < 250; ++i) {
      const double t = s * 25.0 + i * 0.1;
      samples.times.push_back(t);
      const bool in_segment = i < 200;
      samples.angles.push_back(
          in_segment ? wrap_angle(truth + segment_offset + noise * normal(generator)) : NAN);
      if (i == 0) samples.segmentation.segments.push_back({samples.times.size() - 1, 0, t, 0});
      if (i == 199) {
        samples.segmentation.segments.back().end = samples.times.size();
        samples.segmentation.segments.back().end_time = t;
      }
    }
  }
  return samples;
}

TEST(SegmentAverage, RecoversTheAngleAndItsSpreadFromManySegments) {
  const double truth = rad_from_deg(2.0);
  const double segment_sigma = rad_from_deg(0.05);
  const Samples samples = make_samples(truth, 20, rad_from_deg(0.1), segment_sigma, 7);
  const SegmentAverage average =
      average_over_segments(samples.times, samples.angles, samples.segmentation);
  ASSERT_EQ(average.segments.size(), 20u);
  // Standard error ~ segment_sigma / sqrt(20) = 0.011 deg; the estimate lies within 4 of them.
  EXPECT_NEAR(deg_from_rad(average.standard_error), 0.011, 0.005);
  EXPECT_THAT(average.value, AngleNearDeg(truth, 4 * 0.011));
  for (const SegmentEstimate& segment : average.segments) {
    EXPECT_NEAR(segment.weight, 19.9, 1e-9);
    EXPECT_EQ(segment.samples + segment.outliers, 200);
  }
}

TEST(SegmentAverage, RejectsOutliersInsideASegment) {
  const double truth = rad_from_deg(-3.0);
  Samples samples = make_samples(truth, 6, rad_from_deg(0.05), 0.0, 3);
  // Ten wild samples in the second segment, 20 deg off, and one half a turn off.
  for (int i = 0; i < 10; ++i) samples.angles[250 + 10 * i] += rad_from_deg(20.0);
  samples.angles[260 + 5] = wrap_angle(samples.angles[265] + kPi);
  const SegmentAverage average =
      average_over_segments(samples.times, samples.angles, samples.segmentation);
  EXPECT_GE(average.segments[1].outliers, 11);
  EXPECT_EQ(average.inliers[250], 0);
  EXPECT_THAT(average.value, AngleNearDeg(truth, 0.01));
}

TEST(SegmentAverage, AveragesAcrossThePiSeam) {
  const double truth = kPi - rad_from_deg(0.02);
  const Samples samples = make_samples(truth, 6, rad_from_deg(0.1), 0.0, 11);
  const SegmentAverage average =
      average_over_segments(samples.times, samples.angles, samples.segmentation);
  EXPECT_THAT(average.value, AngleNearDeg(truth, 0.01));
  EXPECT_LT(deg_from_rad(average.standard_error), 0.01);
}

TEST(SegmentAverage, FewSegmentsTakeTheStandardErrorFromMovingBlocks) {
  const double noise = rad_from_deg(0.1);
  const Samples samples = make_samples(0.3, 2, noise, 0.0, 5);
  const SegmentAverage average =
      average_over_segments(samples.times, samples.angles, samples.segmentation);
  // Two segments: too few for their spread.
  EXPECT_EQ(average.spread_standard_error, 0.0);
  // White noise: noise / sqrt(400 samples) = 0.005 deg, the formal one; the moving blocks (10 s,
  // 40 s of samples: 4.5 degrees of freedom, Student-t x 1.35) see about as much.
  EXPECT_NEAR(deg_from_rad(average.formal_standard_error), 0.005, 0.0005);
  EXPECT_NEAR(deg_from_rad(average.block_standard_error), 1.35 * 0.005, 0.003);
  EXPECT_GE(average.standard_error, average.formal_standard_error);
}

TEST(SegmentAverage, CorrelatedErrorsWidenTheStandardError) {
  // Three segments whose offsets differ by 0.2 deg (sigma): the formal error of 600 samples knows
  // nothing of it; the segments' spread and the moving blocks do.
  const Samples samples = make_samples(0.3, 3, rad_from_deg(0.05), rad_from_deg(0.2), 9);
  const SegmentAverage average =
      average_over_segments(samples.times, samples.angles, samples.segmentation);
  EXPECT_LT(deg_from_rad(average.formal_standard_error), 0.01);
  EXPECT_GT(deg_from_rad(average.spread_standard_error), 0.03);
  EXPECT_GT(deg_from_rad(average.standard_error), 0.03);
}

TEST(SegmentAverage, RejectsBadArguments) {
  const Samples samples = make_samples(0.0, 2, 0.01, 0.0, 1);
  EXPECT_THROW(average_over_segments(samples.times, samples.angles, Segmentation{}),
               std::invalid_argument);
  const std::vector<double> fewer(samples.times.begin(), samples.times.end() - 1);
  EXPECT_THROW(average_over_segments(fewer, samples.angles, samples.segmentation),
               std::invalid_argument);
  std::vector<double> with_nan = samples.angles;
  with_nan[3] = NAN;
  EXPECT_THROW(average_over_segments(samples.times, with_nan, samples.segmentation),
               std::invalid_argument);
  EXPECT_THROW(average_over_segments(samples.times, samples.angles, samples.segmentation,
                                     {.min_segments_for_spread = 1}),
               std::invalid_argument);
}

}  // namespace
}  // namespace x2car
