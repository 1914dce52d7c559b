#include "x2car/io/bag_tf.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::io {
namespace {

FrameTransform link(const std::string& parent, const std::string& child, double yaw_deg,
                    const Eigen::Vector3d& translation) {
  FrameTransform transform;
  transform.parent = parent;
  transform.child = child;
  transform.parent_from_child.linear() = rotation_from_euler({0.0, 0.0, rad_from_deg(yaw_deg)});
  transform.parent_from_child.translation() = translation;
  return transform;
}

// base_link -> mount (yaw 90, at 1 0 2) -> lidar (yaw -90, 0.5 ahead of the mount): the lidar
// faces forward, 0.5 m to the left of the mount.
TEST(ChainTransform, ComposesFromTheRootDown) {
  const std::vector<FrameTransform> tree = {link("base_link", "mount", 90.0, {1.0, 0.0, 2.0}),
                                            link("mount", "lidar", -90.0, {0.5, 0.0, 0.0}),
                                            link("base_link", "radar", 0.0, {3.0, 0.0, 0.5})};
  const auto base_from_lidar = chain_transform(tree, "base_link", "lidar");
  ASSERT_TRUE(base_from_lidar.has_value());
  EXPECT_TRUE(base_from_lidar->linear().isIdentity(1e-12));
  EXPECT_TRUE(base_from_lidar->translation().isApprox(Eigen::Vector3d(1.0, 0.5, 2.0), 1e-12));
  EXPECT_TRUE(
      chain_transform(tree, "base_link", "base_link")->isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(chain_transform(tree, "base_link", "camera").has_value());
  EXPECT_FALSE(chain_transform(tree, "mount", "radar").has_value());
}

TEST(ChainTransform, ALoopIsNoChain) {
  const std::vector<FrameTransform> loop = {link("a", "b", 0.0, Eigen::Vector3d::Zero()),
                                            link("b", "a", 0.0, Eigen::Vector3d::Zero())};
  EXPECT_FALSE(chain_transform(loop, "base_link", "a").has_value());
}

}  // namespace
}  // namespace x2car::io
