// sensor_msgs/CameraInfo messages (ROS 1 or ROS 2 encoding, io/ros_message.hpp) as x2car's camera
// intrinsics (docs/formats.md, "ROS bags"): height, width, distortion_model, D, K, R, P, binning,
// ROI. The raw image's camera is K with D (the rules of a camera_info YAML file,
// camera_info_yaml.hpp); a rectified image's (`rectified`: the image topic is image_rect...) is the
// projection P's fx, fy, cx, cy without distortion.
#pragma once

#include <string>
#include <string_view>

#include "x2car/core/camera_model.hpp"
#include "x2car/io/ros_message.hpp"

namespace x2car::io {

struct StampedCameraInfo {
  RosHeader header;
  core::CameraIntrinsics intrinsics;
};

// InputError naming the source and field for a message that ends early, non-finite numbers, an
// unknown or unsupported distortion model, a coefficient count that does not fit it, or
// intrinsics that fail Check().
StampedCameraInfo decode_camera_info(std::string_view bytes, RosEncoding encoding,
                                     const std::string& source, bool rectified = false);

}  // namespace x2car::io
