#include "x2car/core/calibration_result.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace x2car {
namespace {

TEST(CalibrationResult, StatusNamesRoundTrip) {
  for (const auto status : {CalibrationStatus::kOk, CalibrationStatus::kInsufficientData,
                            CalibrationStatus::kUnreliable}) {
    EXPECT_EQ(calibration_status_from_string(to_string(status)), status);
  }
  EXPECT_STREQ(to_string(CalibrationStatus::kInsufficientData), "insufficient_data");
  EXPECT_STREQ(to_string(CalibrationStatus::kUnreliable), "unreliable");
  EXPECT_THROW(calibration_status_from_string("fine"), std::invalid_argument);
}

TEST(CalibrationResult, InsufficientDataCarriesItsReasonAndNoAngles) {
  const CalibrationResult result = insufficient_data("ins", "only 4 s of straight driving");
  EXPECT_FALSE(result.ok());
  EXPECT_EQ(result.reason, "only 4 s of straight driving");
  EXPECT_FALSE(result.roll.has_value());
  EXPECT_FALSE(result.pitch.has_value());
  EXPECT_FALSE(result.yaw.has_value());
}

TEST(CalibrationResult, UnobservedAnglesAreZeroOnlyWhenAskedFor) {
  CalibrationResult result;
  result.status = CalibrationStatus::kOk;
  result.yaw = 0.02;
  const EulerAngles angles = result.angles_or_zero();
  EXPECT_EQ(angles.yaw, 0.02);
  EXPECT_EQ(angles.roll, 0.0);
  EXPECT_FALSE(result.roll.has_value());
}

TEST(CalibrationResult, MarkUnreliableKeepsTheEstimateButIsNotOk) {
  CalibrationResult result;
  result.status = CalibrationStatus::kOk;
  result.yaw = 0.5;
  result.yaw_std = 0.01;
  const CalibrationResult marked = mark_unreliable(result, "residual spread 2.1 m/s > 0.5 m/s");
  EXPECT_FALSE(marked.ok());
  EXPECT_EQ(marked.status, CalibrationStatus::kUnreliable);
  EXPECT_EQ(marked.reason, "residual spread 2.1 m/s > 0.5 m/s");
  ASSERT_TRUE(marked.yaw.has_value());
  EXPECT_DOUBLE_EQ(*marked.yaw, 0.5);
}

}  // namespace
}  // namespace x2car
