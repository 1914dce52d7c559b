// A pinhole camera's intrinsics and the file that holds them, `camera/intrinsics.yaml`
// (docs/formats.md):
//
//   width: 1920                     # image size [pixels]
//   height: 1080
//   fx: 1200                        # focal lengths [pixels]
//   fy: 1200
//   cx: 959.5                       # principal point [pixels]; (0, 0) is the centre of the
//   cy: 539.5                       #   top-left pixel, x right, y down (OpenCV)
//   distortion_model: none          # none | plumb_bob
//   distortion_coefficients: []     # none: empty; plumb_bob: [k1, k2, p1, p2, k3] (OpenCV order)
//
// The projection is OpenCV's, in the camera's optical frame O (x right, y down, z forward;
// docs/conventions.md): u = fx x' + cx, v = fy y' + cy with (x', y') = distort(x / z, y / z).
// Numbers are written shortest-round-trip, so a written file reads back to the same values.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace x2car::io {

enum class DistortionModel {
  kNone,      // no coefficients
  kPlumbBob,  // OpenCV / ROS radial-tangential: k1, k2, p1, p2, k3
};

std::string to_string(DistortionModel model);  // "none", "plumb_bob"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
DistortionModel distortion_model_from_string(std::string_view name);
std::vector<std::string> distortion_model_names();  // the valid names, in table order
// How many coefficients the model has: 0 or 5.
std::size_t distortion_coefficient_count(DistortionModel model);

struct CameraIntrinsics {
  int width = 1920;   // [pixels], > 0
  int height = 1080;  // [pixels], > 0
  // A 1920 px wide sensor behind a lens of ~77 deg horizontal field of view, a common automotive
  // front camera.
  double fx = 1200.0;  // [pixels], > 0
  double fy = 1200.0;  // [pixels], > 0
  double cx = 959.5;   // [pixels]: the image centre, (width - 1) / 2; inside [0, width]
  double cy = 539.5;   // [pixels]: (height - 1) / 2; inside [0, height]
  DistortionModel distortion_model = DistortionModel::kNone;
  std::vector<double> distortion_coefficients;  // as many as the model has

  // K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]].
  Eigen::Matrix3d camera_matrix() const;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;

  bool operator==(const CameraIntrinsics&) const = default;
};

std::string format_camera_intrinsics(const CameraIntrinsics& intrinsics);
// Throws std::invalid_argument when the intrinsics fail Check(); InputError when the file cannot
// be written.
void write_camera_intrinsics(const std::filesystem::path& path, const CameraIntrinsics& intrinsics);

// Every key above is required and no other is allowed. InputError names the file, the line and the
// key: invalid YAML, a missing or unknown key, a size that is not a positive integer, a number
// that is not finite, an unknown model, a coefficient count that does not fit the model, and
// intrinsics that fail Check().
CameraIntrinsics read_camera_intrinsics(const std::filesystem::path& path);
CameraIntrinsics parse_camera_intrinsics(std::string_view text, const std::string& source_name);

}  // namespace x2car::io
