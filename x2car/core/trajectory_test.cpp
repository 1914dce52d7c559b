#include "x2car/core/trajectory.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car {
namespace {

using testing::RotationNear;

Trajectory two_pose_trajectory() {
  return Trajectory({{10.0, make_transform(EulerAngles{0, 0, 0.0}, {0, 0, 0})},
                     {12.0, make_transform(EulerAngles{0, 0, 1.0}, {4, -2, 1})}});
}

TEST(Trajectory, InterpolatesPositionLinearlyAndRotationBySlerp) {
  const Trajectory trajectory = two_pose_trajectory();
  const auto pose = trajectory.pose_at(10.5);
  ASSERT_TRUE(pose.has_value());
  EXPECT_TRUE(pose->translation().isApprox(Eigen::Vector3d(1, -0.5, 0.25), 1e-12));
  // Slerp about one axis turns at a constant rate: a quarter of the way is a quarter of the angle.
  EXPECT_THAT(Eigen::Matrix3d(pose->linear()),
              RotationNear(rotation_from_euler({0, 0, 0.25}), 1e-9));
}

TEST(Trajectory, ReturnsTheStoredPoseAtItsTimeAndNothingOutside) {
  const Trajectory trajectory = two_pose_trajectory();
  EXPECT_TRUE(trajectory.pose_at(12.0)->translation().isApprox(Eigen::Vector3d(4, -2, 1)));
  EXPECT_TRUE(trajectory.pose_at(10.0)->translation().isZero());
  EXPECT_FALSE(trajectory.pose_at(9.999).has_value());
  EXPECT_FALSE(trajectory.pose_at(12.001).has_value());
  EXPECT_FALSE(Trajectory().pose_at(0.0).has_value());
  const std::vector<double> times = {11.0, 13.0, 10.0};
  const auto poses = trajectory.poses_at(times);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_TRUE(poses[0].has_value());
  EXPECT_FALSE(poses[1].has_value());
  EXPECT_TRUE(poses[2].has_value());
}

TEST(Trajectory, RejectsTimesThatDoNotIncrease) {
  std::vector<StampedPose> poses(3);
  poses[0].time = 0.0;
  poses[1].time = 1.0;
  poses[2].time = 1.0;
  EXPECT_THROW(Trajectory{poses}, std::invalid_argument);
  poses[2].time = NAN;
  EXPECT_THROW(Trajectory{poses}, std::invalid_argument);
}

TEST(Trajectory, ExposesPlanarPositions) {
  const Trajectory trajectory = two_pose_trajectory();
  EXPECT_EQ(trajectory.times(), (std::vector<double>{10.0, 12.0}));
  EXPECT_EQ(trajectory.positions_x(), (std::vector<double>{0.0, 4.0}));
  EXPECT_EQ(trajectory.positions_y(), (std::vector<double>{0.0, -2.0}));
}

}  // namespace
}  // namespace x2car
