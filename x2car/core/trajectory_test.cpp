#include "x2car/core/trajectory.hpp"

#include <gtest/gtest.h>

#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car {
namespace {

using testing::RotationNear;

TEST(InterpolatePose, PositionLinearlyAndRotationBySlerp) {
  const Eigen::Isometry3d a = make_transform(EulerAngles{0, 0, 0.0}, {0, 0, 0});
  const Eigen::Isometry3d b = make_transform(EulerAngles{0, 0, 1.0}, {4, -2, 1});
  const Eigen::Isometry3d pose = interpolate_pose(a, b, 0.25);
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(1, -0.5, 0.25), 1e-12));
  // Slerp about one axis turns at a constant rate: a quarter of the way is a quarter of the angle.
  EXPECT_THAT(Eigen::Matrix3d(pose.linear()),
              RotationNear(rotation_from_euler({0, 0, 0.25}), 1e-9));
  // The ends are the poses themselves.
  EXPECT_TRUE(interpolate_pose(a, b, 0.0).isApprox(a, 1e-12));
  EXPECT_TRUE(interpolate_pose(a, b, 1.0).isApprox(b, 1e-12));
}

}  // namespace
}  // namespace x2car
