// Timestamped SE(3) poses and their interpolation.
#pragma once

#include <Eigen/Geometry>

namespace x2car {

struct StampedPose {
  double time = 0.0;  // [s]
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
};

// Pose between two poses: linear in position, slerp in rotation; `fraction` in [0, 1].
Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double fraction);

}  // namespace x2car
