// A named rigid transform between two frames, e.g. base_link <- lidar (vehicle_from_lidar), and
// the operations that keep the names honest: composing checks that the frames chain up.
#pragma once

#include <Eigen/Geometry>
#include <string>

namespace x2car {

struct Extrinsic {
  std::string parent_frame = "base_link";  // the frame points are mapped into (the vehicle, V)
  std::string child_frame = "sensor";      // the frame points are given in (the sensor, S)
  // parent_from_child: p_parent = R * p_child + t  [m]
  Eigen::Isometry3d parent_from_child = Eigen::Isometry3d::Identity();
};

// child_from_parent, with the frame names swapped.
Extrinsic inverse(const Extrinsic& parent_from_child);

// a_from_c = a_from_b * b_from_c. Throws std::invalid_argument when a_from_b's child frame is not
// b_from_c's parent frame, e.g. vehicle_from_lidar * camera_from_lidar.
Extrinsic compose(const Extrinsic& a_from_b, const Extrinsic& b_from_c);

}  // namespace x2car
