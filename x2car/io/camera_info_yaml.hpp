// Camera intrinsics in the ROS `camera_info` YAML layout (camera_calibration_parsers; the file a
// ROS camera driver loads), and, for reading, OpenCV's FileStorage calibration YAML
// (docs/formats.md):
//
//   image_width: 1242                      # [pixels]
//   image_height: 375
//   camera_name: camera
//   camera_matrix: {rows: 3, cols: 3, data: [fx, 0, cx, 0, fy, cy, 0, 0, 1]}
//   distortion_model: plumb_bob            # plumb_bob (k1 k2 p1 p2 k3) | equidistant (k1..k4)
//   distortion_coefficients: {rows: 1, cols: 5, data: [k1, k2, p1, p2, k3]}
//   rectification_matrix: {rows: 3, cols: 3, data: [1, 0, 0, 0, 1, 0, 0, 0, 1]}
//   projection_matrix: {rows: 3, cols: 4, data: [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0]}
//
// A camera without distortion is written as plumb_bob with five zeros (what ROS writes); reading
// turns an all-zero (or empty) plumb_bob back into core::DistortionModel::kNone, so a file
// round-trips to the same intrinsics. The writer's rectification matrix is the identity and its
// projection matrix [K | 0]: the undistorted pinhole camera with the same K
// (core::undistort_pixel). The reader checks their shapes and numbers but does not use them (a
// monocular camera).
//
// OpenCV's layout (cv::FileStorage, e.g. its calibration sample) starts with `%YAML:1.0` and holds
// `image_width`, `image_height`, `camera_matrix: !!opencv-matrix {rows, cols, dt, data}` and
// `distortion_coefficients: !!opencv-matrix`; other keys are ignored. Its 4 or 5 coefficients are
// plumb_bob unless a `distortion_model: equidistant` key says they are OpenCV fisheye ones.
//
// Numbers are written shortest-round-trip, so a written file reads back to the same values.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/camera_model.hpp"

namespace x2car::io {

// Throws std::invalid_argument when the intrinsics fail Check().
std::string format_camera_info_yaml(const core::CameraIntrinsics& intrinsics,
                                    std::string_view camera_name = "camera");
// As format_camera_info_yaml; InputError when the file cannot be written.
void write_camera_info_yaml(const std::filesystem::path& path,
                            const core::CameraIntrinsics& intrinsics,
                            std::string_view camera_name = "camera");

// Reads either layout (OpenCV's when the text starts with `%YAML:1.0` or holds `!!opencv-matrix`).
// InputError names the file, the line and the field: invalid YAML, a missing key, an unknown key
// (ROS layout), a matrix whose rows/cols/data do not fit, a number that is not finite, a camera
// matrix with skew or a last row other than (0, 0, 1), an unknown or unsupported distortion model
// (rational_polynomial), a coefficient count that does not fit the model, and intrinsics that
// fail Check().
core::CameraIntrinsics read_camera_info_yaml(const std::filesystem::path& path);
core::CameraIntrinsics parse_camera_info_yaml(std::string_view text,
                                              const std::string& source_name);

// The rules every camera_info source shares (this file and sensor_msgs/CameraInfo messages,
// ros_camera_info.hpp). The model of a distortion_model name: plumb_bob, equidistant (or OpenCV's
// fisheye); std::invalid_argument for rational_polynomial or an unknown name.
core::DistortionModel camera_info_distortion_model(std::string_view name);
// Sets the coefficients for `model`: plumb_bob takes 4 (k3 = 0) or 5, or OpenCV's 8, 12 or 14
// with zeros beyond k3; no or all-zero coefficients mean no distortion; std::invalid_argument for
// a count that does not fit (OpenCV's rational model named as such).
void set_camera_info_distortion(core::CameraIntrinsics& intrinsics, core::DistortionModel model,
                                std::vector<double> coefficients);

}  // namespace x2car::io
