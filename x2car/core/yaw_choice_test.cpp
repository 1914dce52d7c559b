#include "x2car/core/yaw_choice.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace x2car {
namespace {

using ::testing::HasSubstr;

TrackAlignment alignment_with(double track_yaw, double track_std, double velocity_yaw,
                              double velocity_std) {
  TrackAlignment alignment;
  alignment.yaw = SegmentAverage{};
  alignment.yaw->value = track_yaw;
  alignment.yaw->standard_error = track_std;
  alignment.velocity_yaw_estimate = SegmentAverage{};
  alignment.velocity_yaw_estimate->value = velocity_yaw;
  alignment.velocity_yaw_estimate->standard_error = velocity_std;
  return alignment;
}

TEST(YawChoice, AutoReportsTheSmallerStandardErrorAndKeepsBoth) {
  const TrackAlignment alignment = alignment_with(rad_from_deg(2.0), rad_from_deg(0.01),
                                                  rad_from_deg(2.01), rad_from_deg(0.004));
  CalibrationResult result;
  const YawChoice choice = choose_yaw(alignment, YawMethod::kAuto, {});
  write_yaw_choice(choice, result);
  EXPECT_EQ(result.method, "velocity_direction");
  EXPECT_DOUBLE_EQ(*result.yaw, rad_from_deg(2.01));
  EXPECT_DOUBLE_EQ(*result.yaw_std, rad_from_deg(0.004));
  EXPECT_EQ(choice.reported, &*alignment.velocity_yaw_estimate);
  EXPECT_FALSE(choice.disagreement);
  EXPECT_NEAR(result.diagnostics.at("track_method_yaw_deg"), 2.0, 1e-12);
  EXPECT_NEAR(result.diagnostics.at("yaw_disagreement_deg"), 0.01, 1e-12);

  CalibrationResult track;
  write_yaw_choice(choose_yaw(alignment, YawMethod::kTrackHeading, {}), track);
  EXPECT_EQ(track.method, "track_heading");
  EXPECT_DOUBLE_EQ(*track.yaw, rad_from_deg(2.0));
}

TEST(YawChoice, DisagreementNeedsBothTheSigmasAndTheMinimum) {
  // 0.2 deg apart with 0.01 deg standard errors: a disagreement.
  const YawChoice far = choose_yaw(
      alignment_with(rad_from_deg(1.0), rad_from_deg(0.01), rad_from_deg(1.2), rad_from_deg(0.01)),
      YawMethod::kAuto, {});
  ASSERT_TRUE(far.disagreement);
  EXPECT_THAT(*far.disagreement, HasSubstr("differs from the track-heading yaw"));
  // 0.04 deg apart: under the 0.05 deg minimum whatever the standard errors.
  const YawChoice near = choose_yaw(alignment_with(rad_from_deg(1.0), rad_from_deg(0.001),
                                                   rad_from_deg(1.04), rad_from_deg(0.001)),
                                    YawMethod::kAuto, {});
  EXPECT_FALSE(near.disagreement);
  // Across the +-180 deg seam the difference is the short way round.
  const DisagreementTest test;
  EXPECT_FALSE(test(rad_from_deg(179.99), 0.0, rad_from_deg(-179.99), 0.0));
}

TEST(YawChoice, MethodNamesRoundTrip) {
  for (const auto method :
       {YawMethod::kAuto, YawMethod::kTrackHeading, YawMethod::kVelocityDirection}) {
    EXPECT_EQ(yaw_method_from_string(to_string(method)), method);
  }
  EXPECT_THROW(yaw_method_from_string("best"), std::invalid_argument);
  DisagreementTest bad;
  bad.sigmas = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car
