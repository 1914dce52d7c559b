// The frames of a camera recorded in a bag (io/bag.hpp: MCAP, ROS 1 or ROS 2; issue 17 item 2):
// a sensor_msgs/Image or sensor_msgs/CompressedImage topic, one frame per message in the order of
// their header stamps, decoded to 8-bit grey when the calibrator asks for it (from several
// threads). Image encodings: mono8, mono16, rgb8, bgr8, rgba8, bgra8, the four 8-bit Bayer
// patterns and yuv422 (UYVY, YUYV); CompressedImage: whatever OpenCV's imdecode reads (JPEG,
// PNG). The camera's intrinsics come from the sensor_msgs/CameraInfo topic in the image topic's
// namespace (/camera/camera_info for /camera/image_raw/compressed), its first message.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

struct BagFrameOptions {
  // The image topic; unset: the bag's one Image or CompressedImage topic (an error listing them
  // when there are more).
  std::optional<std::string> topic;
  bool allow_truncated = false;
};

struct BagFrames {
  CameraFrameSource source;  // times from header.stamp [s] (Unix stamps kept as they are)
  std::string topic;
  std::string frame_id;  // the first image's header.frame_id
  // From the CameraInfo topic of the image topic's namespace, when the bag has one.
  std::optional<core::CameraIntrinsics> intrinsics;
  std::string info_topic;
};

// InputError naming the bag (and the topic or message) for a bag without an image topic, several
// without --topic (listing them), an unknown topic or one of another type, no messages, two frames
// with one stamp, or a CameraInfo message that does not read; a frame that does not decode is an
// InputError when it is read.
BagFrames camera_frames_from_bag(const std::filesystem::path& bag,
                                 const BagFrameOptions& options = {});

// Whether a CompressedImage's `format` ("jpeg", "bgr8; jpeg compressed bgr8", "png",
// "rgb8; png compressed bgr8", any case) names a lossy codec: all but PNG. Sets the source's
// `lossy` from the topic's first message.
bool compressed_image_format_is_lossy(std::string_view format);

}  // namespace x2car::camera
