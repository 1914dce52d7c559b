#include "x2car/lidar/se3.hpp"

#include <cmath>

namespace x2car::lidar {
Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Isometry3d se3_exp(const Vector6d& twist) {
  const Eigen::Vector3d rho = twist.head<3>();
  const Eigen::Vector3d omega = twist.tail<3>();
  const double theta = omega.norm();
  const Eigen::Matrix3d omega_hat = hat(omega);
  // (1 - cos th)/th^2 and (th - sin th)/th^3, by their series near 0.
  double b = 0.5 - theta * theta / 24.0;
  double c = 1.0 / 6.0 - theta * theta / 120.0;
  if (theta > 1e-4) {
    b = (1.0 - std::cos(theta)) / (theta * theta);
    c = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  const Eigen::Matrix3d v = Eigen::Matrix3d::Identity() + b * omega_hat + c * omega_hat * omega_hat;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(theta, theta > 0.0 ? Eigen::Vector3d(omega / theta)
                                                       : Eigen::Vector3d::UnitX())
                      .toRotationMatrix();
  pose.translation() = v * rho;
  return pose;
}

Vector6d se3_log(const Eigen::Isometry3d& pose) {
  const Eigen::AngleAxisd angle_axis(pose.linear());
  const double theta = angle_axis.angle();
  const Eigen::Vector3d omega = theta * angle_axis.axis();
  const Eigen::Matrix3d omega_hat = hat(omega);
  // V^-1 = I - [w]x/2 + (1/th^2)(1 - th sin th / (2 (1 - cos th))) [w]x^2; the factor is 1/12 at 0.
  double d = 1.0 / 12.0 + theta * theta / 720.0;
  if (theta > 1e-4) {
    d = (1.0 - theta * std::sin(theta) / (2.0 * (1.0 - std::cos(theta)))) / (theta * theta);
  }
  const Eigen::Matrix3d v_inverse =
      Eigen::Matrix3d::Identity() - 0.5 * omega_hat + d * omega_hat * omega_hat;
  Vector6d twist;
  twist << v_inverse * pose.translation(), omega;
  return twist;
}

ScrewMotion::ScrewMotion(const Vector6d& twist_per_second) {
  const Eigen::Vector3d rho = twist_per_second.head<3>();
  const Eigen::Vector3d omega = twist_per_second.tail<3>();
  rho_ = rho.cast<float>();
  omega_ = omega.cast<float>();
  omega_x_rho_ = omega.cross(rho).cast<float>();
  omega_x_omega_x_rho_ = omega.cross(omega.cross(rho)).cast<float>();
  omega_norm2_ = static_cast<float>(omega.squaredNorm());
}

}  // namespace x2car::lidar
