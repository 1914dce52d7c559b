#include "x2car/core/trajectory.hpp"

namespace x2car {

Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double fraction) {
  const Eigen::Quaterniond rotation_a(a.linear());
  const Eigen::Quaterniond rotation_b(b.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation_a.slerp(fraction, rotation_b).toRotationMatrix();
  pose.translation() = (1.0 - fraction) * a.translation() + fraction * b.translation();
  return pose;
}

}  // namespace x2car
