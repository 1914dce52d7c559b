#include "x2car/sim/camera_rays.hpp"

#include <algorithm>
#include <cmath>

namespace x2car::sim {

OpticalRayTable::OpticalRayTable(const core::CameraIntrinsics& intrinsics)
    : width_(static_cast<std::size_t>(intrinsics.width)),
      height_(static_cast<std::size_t>(intrinsics.height)) {
  plane_.reserve(width_ * height_);
  for (int v = 0; v < intrinsics.height; ++v) {
    for (int u = 0; u < intrinsics.width; ++u) {
      const Eigen::Vector3d ray = core::pixel_to_ray(intrinsics, Eigen::Vector2d(u, v));
      plane_.push_back((ray.head<2>() / ray.z()).cast<float>());
    }
  }
}

Eigen::Vector3f OpticalRayTable::at(double u, double v) const {
  // The cell of four pixel centres around (u, v), the border cells extended outwards.
  const auto last_u = static_cast<double>(width_ > 1 ? width_ - 2 : 0);
  const auto last_v = static_cast<double>(height_ > 1 ? height_ - 2 : 0);
  const double u0 = std::clamp(std::floor(u), 0.0, last_u);
  const double v0 = std::clamp(std::floor(v), 0.0, last_v);
  const auto i = static_cast<std::size_t>(u0);
  const auto j = static_cast<std::size_t>(v0);
  const std::size_t i1 = std::min(i + 1, width_ - 1);
  const std::size_t j1 = std::min(j + 1, height_ - 1);
  const auto a = static_cast<float>(u - u0);
  const auto b = static_cast<float>(v - v0);
  const Eigen::Vector2f top = plane_[j * width_ + i] * (1.0f - a) + plane_[j * width_ + i1] * a;
  const Eigen::Vector2f bottom =
      plane_[j1 * width_ + i] * (1.0f - a) + plane_[j1 * width_ + i1] * a;
  const Eigen::Vector2f p = top * (1.0f - b) + bottom * b;
  return Eigen::Vector3f(p.x(), p.y(), 1.0f).normalized();
}

}  // namespace x2car::sim
