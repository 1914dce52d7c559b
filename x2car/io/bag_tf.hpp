// A bag's own idea of where its sensors sit (issue 17 item 2): the tf2_msgs/TFMessage topics
// (/tf_static, the robot_state_publisher's fixed joints, and /tf), as geometry_msgs/
// TransformStamped parent -> child transforms. The mounting of a sensor frame is the chain from
// the car's frame (base_link) down to it, reported beside the calibrated one as "before -> after"
// (core::MountingPrior) and, for the radar, its lever arm.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"

namespace x2car::io {

struct FrameTransform {
  std::string parent;
  std::string child;
  Eigen::Isometry3d parent_from_child = Eigen::Isometry3d::Identity();
  std::string topic;  // where it was read
};

// Every child frame's transform: from a /tf_static-like topic (any TFMessage topic whose name ends
// in tf_static) when there is one, else the first on another TFMessage topic (/tf). InputError
// naming the bag and message for a message that does not read or a quaternion far from unit
// length.
std::vector<FrameTransform> read_bag_transforms(const std::filesystem::path& bag,
                                                bool allow_truncated = false);

// parent_from_child composed along the tree from `root` down to `frame`; unset when `frame` does
// not hang below `root` (or the tree has a loop).
std::optional<Eigen::Isometry3d> chain_transform(const std::vector<FrameTransform>& transforms,
                                                 const std::string& root, const std::string& frame);

// The mounting of `frame` below `root` from the bag's transforms, as a prior (source: the bag and
// the topics); unset when the bag has none for it.
std::optional<MountingPrior> mounting_prior_from_bag(const std::filesystem::path& bag,
                                                     const std::string& frame,
                                                     const std::string& root = "base_link");

}  // namespace x2car::io
