#include "x2car/sim/camera_model.hpp"

namespace x2car::sim {

void CameraOptions::Check() const {
  // CameraIntrinsics::Check names its struct and field ("CameraIntrinsics.fx ...").
  intrinsics.Check();
  core::check_every_pixel_has_a_ray(intrinsics);
}

Eigen::Matrix3d camera_body_from_optical() {
  Eigen::Matrix3d body_from_optical;
  body_from_optical << 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0;
  return body_from_optical;
}

Eigen::Isometry3d world_from_camera_optical(const Eigen::Isometry3d& world_from_vehicle,
                                            const Eigen::Isometry3d& vehicle_from_camera) {
  Eigen::Isometry3d camera_from_optical = Eigen::Isometry3d::Identity();
  camera_from_optical.linear() = camera_body_from_optical();
  return world_from_vehicle * vehicle_from_camera * camera_from_optical;
}

}  // namespace x2car::sim
