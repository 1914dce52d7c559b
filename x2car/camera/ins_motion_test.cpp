#include "x2car/camera/ins_motion.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace x2car::camera {
namespace {

// 20 s at 100 Hz, 10 m/s; the car turns left at 0.2 rad/s from 5 s to 10 s, crossing the +-pi seam.
std::vector<io::InsRecord> drive(bool with_velocity) {
  std::vector<io::InsRecord> records;
  double yaw = 3.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (int i = 0; i <= 2000; ++i) {
    const double time = 0.01 * i;
    io::InsRecord record;
    record.time = time;
    record.attitude.yaw = wrap_angle(yaw);
    const Eigen::Vector3d velocity(10.0 * std::cos(yaw), 10.0 * std::sin(yaw), 0.0);
    if (with_velocity) record.velocity_enu = velocity;
    record.position_enu = position;
    records.push_back(record);
    position += 0.01 * velocity;
    if (time >= 5.0 && time < 10.0) yaw += 0.2 * 0.01;
  }
  return records;
}

TEST(InsMotion, SpeedAndYawRateAtTheFrames) {
  for (const bool with_velocity : {true, false}) {
    const std::vector<io::InsRecord> records = drive(with_velocity);
    const std::vector<double> frames = {100.0 + 2.005, 100.0 + 7.005, 100.0 + 15.0, 100.0 + 25.0,
                                        99.0};
    const std::vector<std::optional<VehicleMotion>> motion =
        motion_from_ins(frames, records, {.ins_to_frame_offset_s = 100.0});
    ASSERT_EQ(motion.size(), 5U);
    ASSERT_TRUE(motion[0] && motion[1] && motion[2]);
    EXPECT_NEAR(motion[0]->speed_mps, 10.0, 1e-3);
    EXPECT_NEAR(motion[0]->yaw_rate, 0.0, 1e-9);
    EXPECT_NEAR(motion[1]->speed_mps, 10.0, 1e-3);
    EXPECT_NEAR(motion[1]->yaw_rate, 0.2, 1e-6);  // across the seam too
    EXPECT_NEAR(motion[2]->yaw_rate, 0.0, 1e-9);
    EXPECT_FALSE(motion[3]);  // after the log
    EXPECT_FALSE(motion[4]);  // before it
  }
}

TEST(InsMotion, GapsGiveNoMotion) {
  std::vector<io::InsRecord> records = drive(true);
  records.erase(records.begin() + 100, records.begin() + 400);  // 1 s to 4 s missing
  const std::vector<std::optional<VehicleMotion>> motion =
      motion_from_ins(std::vector<double>{2.0, 0.5}, records);
  EXPECT_FALSE(motion[0]);
  EXPECT_TRUE(motion[1]);
  EXPECT_THROW(motion_from_ins(std::vector<double>{1.0}, records, {.max_record_gap_s = 0.0}),
               std::invalid_argument);
}

// The heading's noise between records 10 ms apart is not a turn, and a speed ramp is an
// acceleration: both are read over rate_span_s.
TEST(InsMotion, YawRateAndAccelerationOverTheSpanNotOneRecord) {
  std::vector<io::InsRecord> records;
  for (int i = 0; i <= 1000; ++i) {
    io::InsRecord record;
    record.time = 0.01 * i;
    const double speed = record.time < 5.0 ? 10.0 : 10.0 + 2.0 * (record.time - 5.0);
    record.velocity_enu = Eigen::Vector3d(speed, 0.0, 0.0);
    // +-0.05 deg of heading noise, alternating: 10 deg/s between neighbouring records.
    record.attitude.yaw = (i % 2 == 0 ? 1.0 : -1.0) * rad_from_deg(0.05);
    records.push_back(record);
  }
  const std::vector<std::optional<VehicleMotion>> motion =
      motion_from_ins(std::vector<double>{2.005, 7.005}, records);
  ASSERT_TRUE(motion[0] && motion[1]);
  EXPECT_LT(std::abs(motion[0]->yaw_rate), rad_from_deg(0.25));
  EXPECT_NEAR(motion[0]->acceleration_mps2, 0.0, 1e-9);
  EXPECT_NEAR(motion[1]->acceleration_mps2, 2.0, 1e-6);
}

// 30 s ahead at 10 m/s along a heading, a stop, then `reverse_s` backing up at 4 m/s (the car
// still faces that heading), at 100 Hz; the device is mounted at `mounting_yaw` from the car's x
// axis.
std::vector<io::InsRecord> drive_then_reverse(double heading, double mounting_yaw,
                                              bool with_velocity, double reverse_s) {
  std::vector<io::InsRecord> records;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  const Eigen::Vector3d ahead(std::cos(heading), std::sin(heading), 0.0);
  for (int i = 0; i <= 3200 + static_cast<int>(100 * reverse_s); ++i) {
    const double time = 0.01 * i;
    const double speed = time < 30.0 ? 10.0 : (time < 32.0 ? 0.0 : -4.0);
    io::InsRecord record;
    record.time = time;
    record.attitude.yaw = wrap_angle(heading + mounting_yaw);
    if (with_velocity) record.velocity_enu = speed * ahead;
    record.position_enu = position;
    records.push_back(record);
    position += 0.01 * speed * ahead;
  }
  return records;
}

// Backing up at 4 m/s passes the speed gate; the scene then flows into the vanishing point as a
// rear camera sees it ahead, so such frames are gated (they were not: the speed is unsigned).
// Whatever the device's mounting, and also when the car backs up nearly as long as it drives ahead
// (a simulated drive of that kind went unflagged while the offsets were averaged as angles).
TEST(InsMotion, BackingUpIsToldFromTheHeadingWhateverTheMounting) {
  const TemporalFilterOptions gate;
  for (const double reverse_s : {6.0, 25.0}) {
    for (const bool with_velocity : {true, false}) {
      for (const double mounting_yaw : {0.0, rad_from_deg(90.0), rad_from_deg(-170.0)}) {
        const std::vector<io::InsRecord> records =
            drive_then_reverse(rad_from_deg(150.0), mounting_yaw, with_velocity, reverse_s);
        const std::vector<std::optional<VehicleMotion>> motion =
            motion_from_ins(std::vector<double>{10.0, 29.0, 31.0, 34.0, 31.0 + reverse_s}, records);
        ASSERT_TRUE(motion[0] && motion[1] && motion[2] && motion[3] && motion[4]);
        const std::string where =
            fmt::format("backing up {} s, velocity {}, mounting yaw {:.2f} rad", reverse_s,
                        with_velocity, mounting_yaw);
        EXPECT_FALSE(motion[0]->reversing) << where;
        EXPECT_FALSE(motion[1]->reversing) << where;
        EXPECT_FALSE(motion[2]->reversing) << where;  // standing
        EXPECT_TRUE(motion[3]->reversing) << where;
        EXPECT_TRUE(motion[4]->reversing) << where;
        EXPECT_NEAR(motion[3]->speed_mps, 4.0, 1e-6) << where;
        EXPECT_EQ(motion_gate(motion[0], gate), std::nullopt) << where;
        EXPECT_EQ(motion_gate(motion[3], gate), FrameVerdict::kReversing) << where;
      }
    }
  }
}

// A log whose heading does not follow the car (here a constant, while the car drives round a
// circle) gives nothing to compare the course with: no frame is taken as backing up.
TEST(InsMotion, AHeadingThatDoesNotFollowTheCarFlagsNoReversing) {
  std::vector<io::InsRecord> records;
  for (int i = 0; i <= 6000; ++i) {
    const double time = 0.01 * i;
    const double course = 2.0 * kPi * time / 60.0;  // one circle a minute at 10 m/s
    io::InsRecord record;
    record.time = time;
    record.velocity_enu = Eigen::Vector3d(10.0 * std::cos(course), 10.0 * std::sin(course), 0.0);
    records.push_back(record);  // attitude.yaw stays 0
  }
  std::vector<double> frames;
  for (double time = 1.0; time < 59.0; time += 0.5) frames.push_back(time);
  for (const std::optional<VehicleMotion>& at : motion_from_ins(frames, records)) {
    ASSERT_TRUE(at);
    EXPECT_FALSE(at->reversing);
  }
  EXPECT_THROW(motion_from_ins(frames, records, {.min_heading_agreement = 1.5}),
               std::invalid_argument);
  EXPECT_THROW(motion_from_ins(frames, records, {.min_heading_agreement = 0.0}),
               std::invalid_argument);
}

// A heading that stays put while the car turns says nothing about which way the car faces: driving
// out along a road, turning round at speed and back, the way back would all read as backing up (the
// offsets of a constant heading lie on one axis there), and nothing is flagged.
TEST(InsMotion, AHeadingThatDoesNotTurnWithTheCarFlagsNoReversing) {
  std::vector<io::InsRecord> records;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  for (int i = 0; i <= 6000; ++i) {
    const double time = 0.01 * i;
    double course = 0.0;
    double speed = 10.0;
    if (time >= 30.0 && time < 30.0 + 2.0 * kPi) {  // a half circle of 10 m at 5 m/s
      course = 0.5 * (time - 30.0);
      speed = 5.0;
    } else if (time >= 30.0) {
      course = kPi;
    }
    const Eigen::Vector2d velocity = speed * Eigen::Vector2d(std::cos(course), std::sin(course));
    io::InsRecord record;
    record.time = time;
    record.velocity_enu = Eigen::Vector3d(velocity.x(), velocity.y(), 0.0);
    record.position_enu = Eigen::Vector3d(position.x(), position.y(), 0.0);
    records.push_back(record);  // attitude.yaw stays 0
    position += 0.01 * velocity;
  }
  const std::vector<std::optional<VehicleMotion>> motion =
      motion_from_ins(std::vector<double>{10.0, 45.0, 55.0}, records);
  for (const std::optional<VehicleMotion>& at : motion) {
    ASSERT_TRUE(at);
    EXPECT_FALSE(at->reversing);
  }
  // The same drive with a heading that turns with it: nothing backs up either.
  for (io::InsRecord& record : records) {
    record.attitude.yaw = std::atan2(record.velocity_enu.y(), record.velocity_enu.x());
  }
  for (const std::optional<VehicleMotion>& at :
       motion_from_ins(std::vector<double>{10.0, 45.0, 55.0}, records)) {
    EXPECT_FALSE(at->reversing);
  }
}

// A drive with turns whose heading turns with it, then backing up: told (the heading check passes).
TEST(InsMotion, BackingUpIsToldOnADriveWithTurns) {
  std::vector<io::InsRecord> records;
  double heading = 0.3;
  for (int i = 0; i <= 3800; ++i) {
    const double time = 0.01 * i;
    if ((time >= 10.0 && time < 16.0) || (time >= 20.0 && time < 23.0)) heading += 0.25 * 0.01;
    const double speed = time < 30.0 ? 10.0 : (time < 32.0 ? 0.0 : -4.0);
    const Eigen::Vector2d velocity = speed * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    io::InsRecord record;
    record.time = time;
    record.attitude.yaw = wrap_angle(heading + 0.4);  // the device mounted 0.4 rad off
    record.velocity_enu = Eigen::Vector3d(velocity.x(), velocity.y(), 0.0);
    records.push_back(record);
  }
  const std::vector<std::optional<VehicleMotion>> motion =
      motion_from_ins(std::vector<double>{5.0, 13.0, 26.0, 34.0, 37.0}, records);
  for (std::size_t f = 0; f < motion.size(); ++f) {
    ASSERT_TRUE(motion[f]);
    EXPECT_EQ(motion[f]->reversing, f >= 3) << f;
  }
}

// One record whose course points back (a noisy velocity) does not make its frame a reversing one:
// most records around the frame decide.
TEST(InsMotion, OneRecordPointingBackDoesNotEndAStretch) {
  std::vector<io::InsRecord> records =
      drive_then_reverse(rad_from_deg(30.0), 0.0, /*with_velocity=*/true, 6.0);
  records[1000].velocity_enu = -records[1000].velocity_enu;
  const std::vector<std::optional<VehicleMotion>> motion =
      motion_from_ins(std::vector<double>{10.0, 34.0}, records);
  ASSERT_TRUE(motion[0] && motion[1]);
  EXPECT_FALSE(motion[0]->reversing);
  EXPECT_TRUE(motion[1]->reversing);
}

}  // namespace
}  // namespace x2car::camera
