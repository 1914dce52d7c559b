#include "x2car/radar/radar_position_checks.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

using ::testing::HasSubstr;

PairCounts counts_with(double slope, std::int64_t static_objects, std::int64_t moving_objects) {
  PairCounts counts;
  counts.closing_pairs = 50;
  counts.range_rate_norm = 100.0;
  counts.range_rate_dot = slope * 100.0;
  counts.static_objects = static_objects;
  counts.moving_objects = moving_objects;
  return counts;
}

TEST(RadarPositionChecks, PairsPassOrFailWithTheFigureInTheReason) {
  const RadarPositionMethodOptions options;
  EXPECT_FALSE(check_pairs(counts_with(0.99, 30, 30), 1.01, options));
  const auto flipped = check_pairs(counts_with(-1.0, 30, 30), 1.0, options);
  ASSERT_TRUE(flipped);
  EXPECT_THAT(*flipped, HasSubstr("slope -1.00"));
  const auto scale = check_pairs(counts_with(1.0, 30, 30), 1.2, options);
  ASSERT_TRUE(scale);
  EXPECT_THAT(*scale, HasSubstr("1.200 times"));
  const auto few_static = check_pairs(counts_with(1.0, 5, 95), std::nullopt, options);
  ASSERT_TRUE(few_static);
  EXPECT_THAT(*few_static, HasSubstr("only 5 of 100 objects (5 %)"));
  // Too few closing pairs or static objects to judge: no verdict.
  PairCounts thin = counts_with(-1.0, 2, 95);
  thin.closing_pairs = 10;
  EXPECT_FALSE(check_pairs(thin, std::nullopt, options));
  EXPECT_DOUBLE_EQ(range_rate_slope({}), 0.0);
  EXPECT_DOUBLE_EQ(static_object_fraction(counts_with(1.0, 1, 3)), 0.25);
}

TEST(RadarPositionChecks, AzimuthsThatAreNotRadians) {
  const RadarPositionMethodOptions options;
  std::vector<RadarSample> samples(100);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    samples[i].azimuth = rad_from_deg(-50.0 + static_cast<double>(i));
  }
  EXPECT_NEAR(deg_from_rad(azimuth_span(samples)), 89.0, 1.0);
  EXPECT_FALSE(check_azimuths(samples, azimuth_span(samples), options));
  samples[7].azimuth = 57.0;
  const auto degrees = check_azimuths(samples, azimuth_span(samples), options);
  ASSERT_TRUE(degrees);
  EXPECT_THAT(*degrees, HasSubstr("not in radians"));
  for (RadarSample& sample : samples) sample.azimuth = rad_from_deg(sample.azimuth);
  const auto slit = check_azimuths(samples, azimuth_span(samples), options);
  ASSERT_TRUE(slit);
  EXPECT_THAT(*slit, HasSubstr("radians read as degrees"));
}

// A fit whose pairs scatter more than max_noise_vs_nominal times their predicted sigma is
// unreliable; its yaw is kept for inspection.
TEST(RadarPositionChecks, PairScatterBeyondTheNominalNoiseIsUnreliable) {
  const sim::testing::RadarDrive& drive = sim::testing::urban_radar_drive(1);
  const auto detections =
      sim::testing::radar_detections(drive, 5.0, sim::RadarOptions::conti_ars408(), 1);
  RadarCalibrationOptions options;
  options.method = RadarMethod::kPosition;
  options.lever_arm_in_vehicle = sim::testing::kRadarLeverArm.head<2>();
  options.position.max_noise_vs_nominal = 0.5;  // the simulated radar's is ~1
  const CalibrationResult result = calibrate_radar(detections, drive.simulation.ins, options);
  EXPECT_EQ(result.status, CalibrationStatus::kUnreliable);
  EXPECT_THAT(result.reason, HasSubstr("times their predicted sigma"));
  ASSERT_TRUE(result.yaw);
  EXPECT_NEAR(deg_from_rad(*result.yaw), 5.0, 0.2);
}

}  // namespace
}  // namespace x2car::radar
