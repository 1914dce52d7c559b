#include "x2car/radar/radar_auto.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

namespace testing = sim::testing;

using ::testing::HasSubstr;
using ::testing::StartsWith;

CalibrationResult method_result(const std::string& method, double yaw_deg, double std_deg,
                                std::int64_t static_objects) {
  CalibrationResult result;
  result.sensor = "radar";
  result.method = method;
  result.status = CalibrationStatus::kOk;
  result.yaw = rad_from_deg(yaw_deg);
  result.yaw_std = rad_from_deg(std_deg);
  result.support = {{"static_objects", static_objects}};
  return result;
}

TEST(RadarAuto, ChoosesByAgreementAndSupport) {
  const RadarAutoOptions options;
  // Agreeing: the smaller standard error.
  CalibrationResult chosen =
      choose_radar_method(method_result("velocity", 10.0, 0.03, 0),
                          method_result("position", 10.05, 0.02, 50), options);
  EXPECT_EQ(chosen.method, "position");
  EXPECT_THAT(chosen.reason, HasSubstr("agree"));
  EXPECT_DOUBLE_EQ(chosen.diagnostics.at("velocity_yaw_deg"), 10.0);
  EXPECT_EQ(chosen.support.at("position_static_objects"), 50);
  // Disagreeing: the smaller standard error, the position method only with enough static objects.
  chosen = choose_radar_method(method_result("velocity", 10.0, 0.03, 0),
                               method_result("position", 10.5, 0.05, 50), options);
  EXPECT_EQ(chosen.method, "velocity");
  EXPECT_THAT(chosen.reason, HasSubstr("disagree"));
  chosen = choose_radar_method(method_result("velocity", 10.0, 0.05, 0),
                               method_result("position", 10.5, 0.03, 50), options);
  EXPECT_EQ(chosen.method, "position");
  EXPECT_THAT(chosen.reason, HasSubstr("standard error is smaller"));
  chosen = choose_radar_method(method_result("velocity", 10.0, 0.05, 0),
                               method_result("position", 10.5, 0.03, 6), options);
  EXPECT_EQ(chosen.method, "velocity");
  EXPECT_THAT(chosen.reason, HasSubstr("only 6 static objects"));
  // One failing: the other, saying why.
  CalibrationResult failed = insufficient_data("radar", "no tracks");
  failed.method = "position";
  chosen = choose_radar_method(method_result("velocity", 10.0, 0.03, 0), failed, options);
  EXPECT_TRUE(chosen.ok());
  EXPECT_THAT(chosen.reason, HasSubstr("only the velocity method"));
  EXPECT_THAT(chosen.reason, HasSubstr("no tracks"));
  CalibrationResult failed_velocity = insufficient_data("radar", "too slow");
  failed_velocity.method = "velocity";
  chosen = choose_radar_method(failed_velocity, failed, options);
  EXPECT_FALSE(chosen.ok());
  EXPECT_EQ(chosen.method, "auto");
  EXPECT_THAT(chosen.reason, HasSubstr("too slow"));
  EXPECT_THAT(chosen.reason, HasSubstr("no tracks"));
}

// Issue 12: auto never reports ok from a method that failed its checks, nor from two methods that
// disagree grossly.
TEST(RadarAuto, UnreliableIsNeverOk) {
  const RadarAutoOptions options;
  const CalibrationResult unreliable_velocity =
      mark_unreliable(method_result("velocity", 190.0, 0.03, 0), "the fit fails its checks");
  // The other method ok: that one, naming the failure.
  CalibrationResult chosen =
      choose_radar_method(unreliable_velocity, method_result("position", 10.0, 0.05, 50), options);
  EXPECT_TRUE(chosen.ok());
  EXPECT_EQ(chosen.method, "position");
  EXPECT_THAT(chosen.reason, HasSubstr("unreliable"));
  // The other insufficient: unreliable, both reasons, the unreliable fit's figures kept.
  CalibrationResult failed = insufficient_data("radar", "no tracks");
  failed.method = "position";
  chosen = choose_radar_method(unreliable_velocity, failed, options);
  EXPECT_EQ(chosen.status, CalibrationStatus::kUnreliable);
  EXPECT_EQ(chosen.method, "auto");
  EXPECT_THAT(chosen.reason, HasSubstr("the fit fails its checks"));
  EXPECT_THAT(chosen.reason, HasSubstr("no tracks"));
  EXPECT_DOUBLE_EQ(chosen.diagnostics.at("velocity_ok"), 0.0);
  EXPECT_DOUBLE_EQ(chosen.diagnostics.at("velocity_yaw_deg"), 190.0);
  // Both ok, 180 deg apart (a flipped Doppler sign): unreliable.
  chosen = choose_radar_method(method_result("velocity", 190.0, 0.03, 0),
                               method_result("position", 10.0, 0.05, 50), options);
  EXPECT_EQ(chosen.status, CalibrationStatus::kUnreliable);
  EXPECT_THAT(chosen.reason, HasSubstr("disagree by 180.000 deg"));
}

// On a simulated drive auto reports both methods and says which it chose.
TEST(RadarAuto, ReportsBothMethods) {
  const testing::RadarDrive& drive = testing::urban_radar_drive(2);
  RadarCalibrationOptions auto_with_lever_arm;
  auto_with_lever_arm.method = RadarMethod::kAuto;
  auto_with_lever_arm.lever_arm_in_vehicle = testing::kRadarLeverArm.head<2>();
  const auto detections =
      testing::radar_detections(drive, 20.0, sim::RadarOptions::delphi_esr(), 2);
  const CalibrationResult result =
      calibrate_radar(detections, drive.simulation.ins, auto_with_lever_arm);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_LE(std::abs(deg_from_rad(angle_difference(*result.yaw, rad_from_deg(20.0)))), 0.1);
  EXPECT_THAT(result.method, ::testing::AnyOf("velocity", "position"));
  EXPECT_THAT(result.reason, StartsWith("auto: "));
  EXPECT_NEAR(result.diagnostics.at("velocity_yaw_deg"), 20.0, 0.1);
  EXPECT_NEAR(result.diagnostics.at("position_yaw_deg"), 20.0, 0.2);
  EXPECT_GT(result.support.at("velocity_static_detections"), 1000);
  EXPECT_GT(result.support.at("position_static_objects"), 20);
}

}  // namespace
}  // namespace x2car::radar
