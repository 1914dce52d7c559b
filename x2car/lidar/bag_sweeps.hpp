// The sweeps of a LiDAR recorded in a bag (io/bag.hpp: MCAP, ROS 1 or ROS 2): one
// sensor_msgs/PointCloud2 message per sweep (io/ros_point_cloud2.hpp), in the order of their
// header stamps. The bag is scanned once for the stamps (only the headers are decoded); each
// sweep is then read again and decoded when the calibrator asks for it, from several threads.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "x2car/lidar/lidar_calibration.hpp"

namespace x2car::lidar {

struct BagSweepOptions {
  // The topic; unset: the bag's one PointCloud2 topic (an error listing them when there are more).
  std::optional<std::string> topic;
  bool allow_truncated = false;
};

struct BagSweeps {
  SweepSource source;  // times from header.stamp [s]; Unix stamps are kept as they are
  std::string topic;
  std::string frame_id;  // the first message's header.frame_id
};

// InputError naming the bag (and the topic or message) for a bag without a PointCloud2 topic,
// several without --topic (listing them), an unknown topic (listing those there are), a topic of
// another type, one without messages, or two sweeps with one stamp.
BagSweeps sweeps_from_bag(const std::filesystem::path& bag, const BagSweepOptions& options = {});

}  // namespace x2car::lidar
