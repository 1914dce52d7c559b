#include "x2car/radar/radar_ego_motion.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "x2car/io/ins_csv.hpp"
#include "x2car/io/radar_csv.hpp"

namespace x2car::radar {
namespace {

TEST(RadarEgoMotion, LeverArmAddsYawRateCrossLeverArm) {
  std::vector<io::InsRecord> ins(3);
  for (int i = 0; i < 3; ++i) {
    ins[i].time = i;
    ins[i].velocity_enu = {10.0, 0.0, 0.0};
    ins[i].attitude.yaw = 0.1 * i;  // 0.1 rad/s left
  }
  io::RadarDetection detection;
  detection.time = 1.0;
  const RadarEgoMotion motion =
      radar_ego_motion(std::vector{detection}, ins, Eigen::Vector2d(4.0, 1.0));
  ASSERT_EQ(motion.samples.size(), 1u);
  EXPECT_NEAR(motion.samples[0].yaw_rate, 0.1, 1e-12);
  EXPECT_NEAR(motion.samples[0].radar_velocity_in_vehicle.x(), 10.0 - 0.1 * 1.0, 1e-12);
  EXPECT_NEAR(motion.samples[0].radar_velocity_in_vehicle.y(), 0.1 * 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(radar_to_ins_time_offset(100.5, 100.0), 0.5);
  EXPECT_DOUBLE_EQ(radar_to_ins_time_offset(0.0, 100.0), 0.0);
}

}  // namespace
}  // namespace x2car::radar
