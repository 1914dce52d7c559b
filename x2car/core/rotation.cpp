#include "x2car/core/rotation.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace x2car {

Eigen::Matrix3d rotation_from_euler(const EulerAngles& angles) {
  return quaternion_from_euler(angles).toRotationMatrix();
}

EulerAngles euler_from_rotation(const Eigen::Matrix3d& rotation) {
  // R = Rz(y) Ry(p) Rx(r):  R(2,0) = -sin p,  R(1,0) = sin y cos p,  R(0,0) = cos y cos p.
  const double minus_sin_pitch = std::clamp(rotation(2, 0), -1.0, 1.0);
  const double cos_pitch = std::hypot(rotation(0, 0), rotation(1, 0));
  EulerAngles angles;
  angles.pitch = std::atan2(-minus_sin_pitch, cos_pitch);
  if (cos_pitch < 1e-12) {
    // Gimbal lock: only the combination of roll and yaw is defined; put it all into yaw.
    // With roll = 0 the remaining columns give R(0,1) = -sin y and R(1,1) = cos y.
    angles.yaw = wrap_angle(std::atan2(-rotation(0, 1), rotation(1, 1)));
    return angles;
  }
  angles.yaw = std::atan2(rotation(1, 0), rotation(0, 0));
  // Roll from what is left once yaw and pitch are undone, Rx(r) = Ry(-p) Rz(-y) R, rather than
  // from R(2,1) and R(2,2): near gimbal lock those are tiny and yaw is imprecise, and taking roll
  // from the remainder makes it absorb the yaw error, so the rotation still round-trips.
  const Eigen::Matrix3d roll_only =
      Eigen::AngleAxisd(-angles.pitch, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      Eigen::AngleAxisd(-angles.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * rotation;
  angles.roll = wrap_angle(std::atan2(roll_only(2, 1), roll_only(1, 1)));
  angles.yaw = wrap_angle(angles.yaw);
  return angles;
}

Eigen::Quaterniond quaternion_from_euler(const EulerAngles& angles) {
  return Eigen::AngleAxisd(angles.yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(angles.pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(angles.roll, Eigen::Vector3d::UnitX());
}

EulerAngles euler_from_quaternion(const Eigen::Quaterniond& quaternion) {
  return euler_from_rotation(quaternion.normalized().toRotationMatrix());
}

Eigen::Vector3d rotation_vector_from_rotation(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(Eigen::Quaterniond(rotation).normalized());
  return angle_axis.axis() * angle_axis.angle();
}

Eigen::Matrix3d rotation_from_rotation_vector(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::Quaterniond(a).angularDistance(Eigen::Quaterniond(b));
}

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& matrix) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(matrix, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d reflection_guard = Eigen::Matrix3d::Identity();
  reflection_guard(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixU() * reflection_guard * svd.matrixV().transpose();
}

bool is_rotation(const Eigen::Matrix3d& matrix, double tolerance) {
  if (!matrix.allFinite()) return false;
  const bool orthonormal =
      (matrix.transpose() * matrix - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <=
      tolerance;
  return orthonormal && std::abs(matrix.determinant() - 1.0) <= tolerance;
}

Eigen::Isometry3d make_transform(const Eigen::Matrix3d& rotation,
                                 const Eigen::Vector3d& translation) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = rotation;
  transform.translation() = translation;
  return transform;
}

Eigen::Isometry3d make_transform(const EulerAngles& angles, const Eigen::Vector3d& translation) {
  return make_transform(rotation_from_euler(angles), translation);
}

double wrap_angle(double angle) {
  if (!std::isfinite(angle)) return angle;
  double wrapped = std::remainder(angle, 2.0 * kPi);  // in [-pi, pi]
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

double angle_difference(double a, double b) { return wrap_angle(a - b); }

namespace {

// Sum of weighted unit vectors; its direction is the circular mean, its length / sum of weights the
// mean resultant length.
Eigen::Vector3d resultant(std::span<const double> angles, std::span<const double> weights) {
  if (angles.empty()) throw std::invalid_argument("circular mean of no angles");
  if (!weights.empty() && weights.size() != angles.size()) {
    throw std::invalid_argument("circular mean: angles and weights differ in size");
  }
  double sum_cos = 0.0, sum_sin = 0.0, sum_weights = 0.0;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    const double weight = weights.empty() ? 1.0 : weights[i];
    if (!(weight >= 0.0)) throw std::invalid_argument("circular mean: negative or NaN weight");
    sum_cos += weight * std::cos(angles[i]);
    sum_sin += weight * std::sin(angles[i]);
    sum_weights += weight;
  }
  if (!(sum_weights > 0.0)) throw std::invalid_argument("circular mean: all weights are zero");
  return {sum_cos, sum_sin, sum_weights};
}

// A mean resultant length at most this has no direction: the angles cancel out.
constexpr double kVanishingResultant = 1e-12;

}  // namespace

double circular_mean(std::span<const double> angles, std::span<const double> weights) {
  const Eigen::Vector3d sums = resultant(angles, weights);
  if (std::hypot(sums.x(), sums.y()) <= kVanishingResultant * sums.z()) {
    throw std::invalid_argument("circular mean: the directions cancel out");
  }
  return wrap_angle(std::atan2(sums.y(), sums.x()));
}

double mean_resultant_length(std::span<const double> angles, std::span<const double> weights) {
  const Eigen::Vector3d sums = resultant(angles, weights);
  return std::hypot(sums.x(), sums.y()) / sums.z();
}

std::optional<double> majority_axis_end(std::span<const double> angles, double min_agreement) {
  std::vector<double> doubled;
  doubled.reserve(angles.size());
  for (const double angle : angles) doubled.push_back(2.0 * angle);
  if (doubled.empty()) return std::nullopt;
  const double agreement = mean_resultant_length(doubled);
  if (agreement < min_agreement || agreement <= kVanishingResultant) return std::nullopt;
  const double axis = 0.5 * circular_mean(doubled);
  const auto along_axis = std::ranges::count_if(angles, [axis](double angle) {
    return std::abs(angle_difference(angle, axis)) <= kPi / 2.0;
  });
  return 2 * static_cast<std::size_t>(along_axis) >= angles.size() ? axis : wrap_angle(axis + kPi);
}

double heading_enu_from_azimuth(double azimuth) { return wrap_angle(kPi / 2.0 - azimuth); }

double azimuth_from_heading_enu(double heading_enu) { return wrap_angle(kPi / 2.0 - heading_enu); }

}  // namespace x2car
