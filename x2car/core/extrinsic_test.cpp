#include "x2car/core/extrinsic.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

Extrinsic make(const std::string& parent, const std::string& child, const EulerAngles& angles,
               const Eigen::Vector3d& translation) {
  return {parent, child, make_transform(angles, translation)};
}

TEST(Extrinsic, ComposeChainsFramesAndTransforms) {
  const Extrinsic vehicle_from_lidar = make("base_link", "lidar", {0, 0, kPi / 2}, {1, 0, 2});
  const Extrinsic lidar_from_camera = make("lidar", "camera", {}, {0.5, 0, 0});
  const Extrinsic vehicle_from_camera = compose(vehicle_from_lidar, lidar_from_camera);
  EXPECT_EQ(vehicle_from_camera.parent_frame, "base_link");
  EXPECT_EQ(vehicle_from_camera.child_frame, "camera");
  // The camera sits 0.5 m along the LiDAR's x axis, which points along the vehicle's y axis.
  EXPECT_TRUE(vehicle_from_camera.parent_from_child.translation().isApprox(
      Eigen::Vector3d(1, 0.5, 2), 1e-12));
}

TEST(Extrinsic, ComposeRefusesFramesThatDoNotChain) {
  const Extrinsic vehicle_from_lidar = make("base_link", "lidar", {}, {1, 0, 2});
  const Extrinsic radar_from_camera = make("radar", "camera", {}, {0, 0, 0});
  EXPECT_THROW(compose(vehicle_from_lidar, radar_from_camera), std::invalid_argument);
}

TEST(Extrinsic, InverseSwapsFramesAndUndoesTheTransform) {
  const Extrinsic vehicle_from_lidar = make("base_link", "lidar", {0.1, -0.2, 0.3}, {1, -2, 3});
  const Extrinsic lidar_from_vehicle = inverse(vehicle_from_lidar);
  EXPECT_EQ(lidar_from_vehicle.parent_frame, "lidar");
  EXPECT_EQ(lidar_from_vehicle.child_frame, "base_link");
  const Extrinsic identity = compose(vehicle_from_lidar, lidar_from_vehicle);
  EXPECT_TRUE(identity.parent_from_child.matrix().isIdentity(1e-12));
}

}  // namespace
}  // namespace x2car
