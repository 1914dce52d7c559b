// The camera's rays: which direction of its optical frame O (x right, y down, z forward; DESIGN
// §1) each pixel sees. The one place the renderer meets the lens model, so that a distorted lens
// changes nothing else: the renderer traces these rays and the image comes out distorted.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "x2car/core/camera_model.hpp"

namespace x2car::sim {

// The rays of every pixel centre (core::pixel_to_ray: the lens model, distortion included; pixel
// centres at whole numbers, (0, 0) the top-left pixel's centre, OpenCV), computed once per camera
// (the undistortion of a real lens model costs iterations), each as the point where it meets the
// plane z = 1 of O (x / z, y / z). Between pixel centres the rays are interpolated bilinearly on
// that plane: exact for a pinhole, and within ~1e-4 px of the lens model for the distortions of
// camera lenses (smooth over a pixel).
class OpticalRayTable {
 public:
  explicit OpticalRayTable(const core::CameraIntrinsics& intrinsics);

  // The unit ray through the centre of pixel (u, v).
  Eigen::Vector3f at_centre(int u, int v) const {
    const Eigen::Vector2f& p =
        plane_[static_cast<std::size_t>(v) * width_ + static_cast<std::size_t>(u)];
    return Eigen::Vector3f(p.x(), p.y(), 1.0f).normalized();
  }
  // The unit ray through image point (u, v) [pixels], anywhere on the image (extrapolated at the
  // border half-pixel).
  Eigen::Vector3f at(double u, double v) const;

 private:
  std::size_t width_ = 0;
  std::size_t height_ = 0;
  std::vector<Eigen::Vector2f> plane_;  // row by row (index v * width + u)
};

}  // namespace x2car::sim
