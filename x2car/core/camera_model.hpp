// A camera's intrinsics and its projection: the pinhole matrix K and OpenCV's lens distortion
// models, in the camera's optical frame O (x right, y down, z forward; docs/conventions.md).
//
//   point in O (x, y, z), z > 0  ->  normalised (x / z, y / z)  ->  distorted (x', y')
//   ->  pixel (u, v) = (fx x' + cx, fy y' + cy)
//
// Pixels follow OpenCV: (0, 0) is the centre of the top-left pixel, u right, v down; the image
// spans [-0.5, width - 0.5] x [-0.5, height - 0.5].
//
// Distortion models (the coefficients in OpenCV's order):
// - kNone: x' = x.
// - kPlumbBob (OpenCV's default model, ROS `plumb_bob`): k1 k2 p1 p2 k3,
//     r^2 = x^2 + y^2, R = 1 + k1 r^2 + k2 r^4 + k3 r^6,
//     x' = x R + 2 p1 x y + p2 (r^2 + 2 x^2),  y' = y R + p1 (r^2 + 2 y^2) + 2 p2 x y.
// - kEquidistant (OpenCV's cv::fisheye, ROS `equidistant`): k1 k2 k3 k4,
//     theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//     (x', y') = (theta_d / r) (x, y).
// A model is used only where it is one-to-one: where its radial mapping still grows with the
// radius (its derivative stays positive from the centre out). Beyond that, projection returns
// nullopt rather than a folded-back pixel.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace x2car::core {

enum class DistortionModel {
  kNone,         // no coefficients
  kPlumbBob,     // OpenCV / ROS radial-tangential: k1, k2, p1, p2, k3
  kEquidistant,  // OpenCV fisheye / ROS equidistant: k1, k2, k3, k4
};

std::string to_string(DistortionModel model);  // "none", "plumb_bob", "equidistant"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
DistortionModel distortion_model_from_string(std::string_view name);
std::vector<std::string> distortion_model_names();  // the valid names, in table order
// How many coefficients the model has: 0, 5 or 4.
std::size_t distortion_coefficient_count(DistortionModel model);

// The default is KITTI's rectified front camera (camera_preset("kitti")).
struct CameraIntrinsics {
  int width = 1242;      // [pixels], > 0
  int height = 375;      // [pixels], > 0
  double fx = 721.5377;  // [pixels], 0.05-1000 x width (pinhole_problem)
  double fy = 721.5377;  // [pixels], 0.05-1000 x height
  double cx = 609.5593;  // [pixels], inside [0, width]
  double cy = 172.854;   // [pixels], inside [0, height]
  DistortionModel distortion_model = DistortionModel::kNone;
  std::vector<double> distortion_coefficients;  // as many as the model has

  // K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]].
  Eigen::Matrix3d camera_matrix() const;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;

  bool operator==(const CameraIntrinsics&) const = default;
};

// What is wrong with a camera's fx, fy, cx, cy for its image size, for readers to name the field
// that holds it (CameraIntrinsics::Check's rules for these four).
struct PinholeProblem {
  enum Parameter { kFx, kFy, kCx, kCy } parameter = kFx;
  std::string why;  // "the focal length fx must be positive, found -721.5"

  // Where the parameter sits in a row-major 3 x `cols` camera matrix (3: K, 4: a projection P).
  int matrix_index(int cols = 3) const {
    switch (parameter) {
      case kFx:
        return 0;
      case kFy:
        return cols + 1;
      case kCx:
        return 2;
      case kCy:
        return cols + 2;
    }
    return 0;
  }
};
// None when width and height are positive and the four are a camera's: focal lengths between
// kMinFocalOverSize and kMaxFocalOverSize times the image's width (fx) or height (fy) (a field of
// view between ~0.06 and ~170 deg: anything else is a unit mix-up), the principal point inside the
// image.
inline constexpr double kMinFocalOverSize = 0.05;
inline constexpr double kMaxFocalOverSize = 1000.0;
std::optional<PinholeProblem> pinhole_problem(const CameraIntrinsics& intrinsics);

// Named cameras (issue 13):
// - "kitti": KITTI raw image_02 after rectification (calib_cam_to_cam.txt P_rect_02): 1242x375,
//   fx = fy = 721.5377, (cx, cy) = (609.5593, 172.854), no distortion; ~81 deg horizontal FOV.
// - "automotive_1080p": 1920x1080, fx = fy = 1200 (~77 deg HFOV), principal point at the image
//   centre, mild barrel plumb_bob distortion (~8 % at the corners).
// - "dashcam_wide": 1280x720, equidistant fisheye, ~120 deg HFOV (~69 deg half-angle at the
//   corners), strong distortion; every pixel has a ray and maps back.
// Throws std::invalid_argument listing the names for an unknown one.
CameraIntrinsics camera_preset(std::string_view name);
std::vector<std::string> camera_preset_names();

// The distorted normalised coordinates of an undistorted normalised point (formulas above). Outside
// the model's one-to-one domain the formula is still evaluated (see project_to_pixel).
Eigen::Vector2d distort_normalized(const CameraIntrinsics& intrinsics,
                                   const Eigen::Vector2d& undistorted_normalized);

// The inverse of distort_normalized by Newton's method (residual < 1e-12, ~1e-9 px); nullopt when
// it does not converge, when the solution lies outside the one-to-one domain, or (equidistant) when
// the ray is 90 deg or more off the optical axis, where normalised coordinates do not exist.
std::optional<Eigen::Vector2d> undistort_normalized(const CameraIntrinsics& intrinsics,
                                                    const Eigen::Vector2d& distorted_normalized);

// The distorted pixel of a point in O; nullopt for a point on or behind the image plane (z <= 0)
// and outside the model's one-to-one domain. The pixel may lie outside the image.
std::optional<Eigen::Vector2d> project_to_pixel(const CameraIntrinsics& intrinsics,
                                                const Eigen::Vector3d& point_optical);

// The unit ray in O through a (distorted) pixel, z > 0 inside the model's domain. Costs one
// Newton solve with distortion (~0.1 us), a division without; a renderer tracing many rays per
// pixel may tabulate it. For a pixel whose undistortion fails (outside the one-to-one domain; see
// check_every_pixel_has_a_ray) it returns the ray of the best Newton iterate: finite, never NaN.
Eigen::Vector3d pixel_to_ray(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel);

// The undistorted pixel K (x, y, 1) of a distorted pixel: where a pinhole camera with the same K
// would see the same ray. Falls back like pixel_to_ray; for an equidistant ray at 90 deg or more
// off axis the result is pushed far out along the ray's direction (finite).
Eigen::Vector2d undistort_pixel(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel);

// Throws std::invalid_argument naming the first pixel on the image's border (sampled every 4 px
// and at the corners) whose ray does not project back to it within 0.01 px: the distortion is
// not one-to-one over the image. The radial distortion peaks at the border, so the border decides.
void check_every_pixel_has_a_ray(const CameraIntrinsics& intrinsics);

}  // namespace x2car::core
