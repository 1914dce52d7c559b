// A named rigid transform between two frames, e.g. base_link <- lidar (vehicle_from_lidar).
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

}  // namespace x2car
