#include "x2car/sim/camera_model.hpp"

namespace x2car::sim {

void CameraOptions::Check() const {
  // CameraIntrinsics::Check names its struct and field ("CameraIntrinsics.fx ...").
  intrinsics.Check();
}

Eigen::Matrix3d camera_body_from_optical() {
  Eigen::Matrix3d body_from_optical;
  body_from_optical << 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0;
  return body_from_optical;
}

}  // namespace x2car::sim
