// The exponential and logarithm of SE(3) for the LiDAR odometry: constant-velocity prediction and
// deskewing move a pose along a constant twist (a screw motion), which is what a car turning at a
// steady rate does over one sweep; interpolating rotation and translation separately would cut
// the corner of the arc.
//
// A twist xi = (rho, omega) holds the translational part rho [m] first and the rotation vector
// omega [rad] second; exp(xi) = [exp([omega]x), V(omega) rho; 0, 1] with
// V = I + (1 - cos th)/th^2 [omega]x + (th - sin th)/th^3 [omega]x^2, th = |omega| (Barfoot,
// "State Estimation for Robotics", eq. 7.85-7.86).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

namespace x2car::lidar {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// The skew-symmetric matrix [v]x, with [v]x u = v x u.
Eigen::Matrix3d hat(const Eigen::Vector3d& v);

Eigen::Isometry3d se3_exp(const Vector6d& twist);
Vector6d se3_log(const Eigen::Isometry3d& pose);

// exp(tau * twist) applied to many points at many tau, cheaply: the coefficients of the Rodrigues
// and V formulas are evaluated per point as power series in tau (exact to float precision while
// |omega| tau <= kSeriesLimit) or with sin/cos beyond. Used to deskew a sweep: `twist` is the
// motion per second in the sensor frame, tau the point's time relative to the reference time [s].
class ScrewMotion {
 public:
  explicit ScrewMotion(const Vector6d& twist_per_second);

  // exp(tau * twist) * point. Inline: it runs once per point of every sweep.
  Eigen::Vector3f apply(const Eigen::Vector3f& point, float tau) const {
    // With W = [omega]x, w = |omega|, th = w tau:
    //   R(tau) = I + (sin th / w) W + ((1 - cos th) / w^2) W^2
    //   t(tau) = tau rho + ((1 - cos th) / w^2) W rho + ((th - sin th) / w^3) W^2 rho
    const float tau2 = tau * tau;
    const float theta2 = omega_norm2_ * tau2;
    float a, b, c;  // sin th / w, (1 - cos th) / w^2, (th - sin th) / w^3
    if (theta2 <= kSeriesLimit * kSeriesLimit) {
      a = tau * (1.0f - theta2 / 6.0f * (1.0f - theta2 / 20.0f));
      b = tau2 * (0.5f - theta2 / 24.0f * (1.0f - theta2 / 30.0f));
      c = tau2 * tau * (1.0f / 6.0f - theta2 / 120.0f * (1.0f - theta2 / 42.0f));
    } else {
      const float w = std::sqrt(omega_norm2_);
      const float theta = w * tau;
      a = std::sin(theta) / w;
      b = (1.0f - std::cos(theta)) / omega_norm2_;
      c = (theta - std::sin(theta)) / (omega_norm2_ * w);
    }
    // W p = omega x p, W^2 p = omega x (omega x p); spelled out so that it inlines at -O2.
    const Eigen::Vector3f wp = omega_.cross(point);
    const Eigen::Vector3f wwp = omega_.cross(wp);
    return point + a * wp + b * wwp + tau * rho_ + b * omega_x_rho_ + c * omega_x_omega_x_rho_;
  }

 private:
  static constexpr float kSeriesLimit = 0.5f;  // [rad]; the series' error is ~th^7/5040 there
  Eigen::Vector3f rho_;                        // [m/s]
  Eigen::Vector3f omega_;                      // [rad/s]
  Eigen::Vector3f omega_x_rho_, omega_x_omega_x_rho_;
  float omega_norm2_ = 0.0f;  // |omega|^2 [rad^2/s^2]
};

}  // namespace x2car::lidar
