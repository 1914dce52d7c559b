#include "x2car/sim/camera_model.hpp"

#include <stdexcept>
#include <string>

namespace x2car::sim {

void CameraOptions::Check() const {
  try {
    intrinsics.Check();
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("camera: ") + error.what());
  }
}

Eigen::Matrix3d camera_body_from_optical() {
  Eigen::Matrix3d body_from_optical;
  body_from_optical << 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0;
  return body_from_optical;
}

}  // namespace x2car::sim
