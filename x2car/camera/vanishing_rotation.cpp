#include "x2car/camera/vanishing_rotation.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace x2car::camera {

Eigen::Matrix3d body_from_optical() {
  Eigen::Matrix3d rotation;
  rotation << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return rotation;
}

namespace {

// Below this a normalised vector is taken as zero: the inputs are pixels and lines of ordinary
// magnitude, so only a truly degenerate geometry gets near it.
constexpr double kDegenerate = 1e-12;

bool finite(const Eigen::Vector3d& vector) { return vector.allFinite(); }

}  // namespace

std::optional<Eigen::Matrix3d> optical_from_vehicle(const Eigen::Vector3d& forward_in_optical,
                                                    const Eigen::Vector3d& up_in_optical) {
  if (!finite(forward_in_optical) || !finite(up_in_optical)) return std::nullopt;
  const double forward_norm = forward_in_optical.norm();
  const double up_norm = up_in_optical.norm();
  if (forward_norm < kDegenerate || up_norm < kDegenerate) return std::nullopt;
  // eq:camera_R3: the forward ray, in front of the camera.
  Eigen::Vector3d forward = forward_in_optical / forward_norm;
  if (forward.z() < 0.0) forward = -forward;
  // The horizon's plane normal, pointing up (y < 0 in O), orthogonalised against the forward ray:
  // the vanishing point fixes pitch and yaw, the horizon adds only the roll about it.
  Eigen::Vector3d up = up_in_optical / up_norm;
  if (up.y() > 0.0) up = -up;
  up -= up.dot(forward) * forward;
  const double orthogonal_norm = up.norm();
  if (orthogonal_norm < 1e-9) return std::nullopt;
  up /= orthogonal_norm;
  Eigen::Matrix3d rotation;
  rotation.col(0) = forward;
  rotation.col(1) = up.cross(forward);  // the car's y axis (left) = z x x
  rotation.col(2) = up;
  return rotation;
}

Eigen::Matrix3d vehicle_from_camera_body(const Eigen::Matrix3d& optical_from_vehicle) {
  // R_V_B = R_V_O R_O_B = R_O_V^T R_B_O^T.
  return optical_from_vehicle.transpose() * body_from_optical().transpose();
}

std::optional<Eigen::Matrix3d> vehicle_from_camera_rotation(
    const Eigen::Vector2d& vanishing_point_px, const Eigen::Vector3d& horizon_line,
    const Eigen::Matrix3d& camera_matrix) {
  if (!vanishing_point_px.allFinite() || !finite(horizon_line) || !camera_matrix.allFinite()) {
    return std::nullopt;
  }
  const Eigen::Vector3d forward =
      camera_matrix.inverse() *
      Eigen::Vector3d(vanishing_point_px.x(), vanishing_point_px.y(), 1.0);
  // A line l holds the images of the rays d with l . K d = 0: its plane's normal is K^T l.
  const Eigen::Vector3d up = camera_matrix.transpose() * horizon_line;
  const std::optional<Eigen::Matrix3d> rotation = optical_from_vehicle(forward, up);
  if (!rotation) return std::nullopt;
  return vehicle_from_camera_body(*rotation);
}

std::optional<EulerAngles> vehicle_from_camera_angles(const Eigen::Vector2d& vanishing_point_px,
                                                      const Eigen::Vector3d& horizon_line,
                                                      const Eigen::Matrix3d& camera_matrix) {
  const std::optional<Eigen::Matrix3d> rotation =
      vehicle_from_camera_rotation(vanishing_point_px, horizon_line, camera_matrix);
  if (!rotation) return std::nullopt;
  return euler_from_rotation(*rotation);
}

std::optional<Eigen::Vector3d> horizon_from_up(const Eigen::Vector3d& up_in_optical,
                                               const Eigen::Matrix3d& camera_matrix) {
  if (!finite(up_in_optical) || up_in_optical.norm() < kDegenerate) return std::nullopt;
  // The plane through the camera centre with normal u meets the image in the polar line K^-T u.
  Eigen::Vector3d line = camera_matrix.inverse().transpose() * up_in_optical;
  const double scale = line.head<2>().norm();
  if (!(scale > kDegenerate * line.norm())) return std::nullopt;
  line /= scale;
  if (line.y() < 0.0) line = -line;
  return line;
}

std::optional<VanishingGeometry> vanishing_geometry_from_rotation(
    const Eigen::Matrix3d& vehicle_from_camera, const Eigen::Matrix3d& camera_matrix) {
  // R_O_V = (R_V_B R_B_O)^T: its columns are the car's axes in O.
  const Eigen::Matrix3d optical_from_vehicle_rotation =
      (vehicle_from_camera * body_from_optical()).transpose();
  const Eigen::Vector3d forward = optical_from_vehicle_rotation.col(0);
  if (!(forward.z() > kDegenerate)) return std::nullopt;
  const Eigen::Vector3d image = camera_matrix * forward;
  const std::optional<Eigen::Vector3d> horizon =
      horizon_from_up(optical_from_vehicle_rotation.col(2), camera_matrix);
  if (!horizon) return std::nullopt;
  VanishingGeometry geometry;
  geometry.vanishing_point_px = image.head<2>() / image.z();
  geometry.horizon_line = *horizon;
  return geometry;
}

double horizon_angle(const Eigen::Vector3d& horizon_line) {
  // Direction along the line (b, -a) in (u, v); with v pointing down, a person sees (b, a).
  double angle = std::atan2(horizon_line.x(), horizon_line.y());
  if (angle > kPi / 2.0) angle -= kPi;
  if (angle <= -kPi / 2.0) angle += kPi;
  return angle;
}

}  // namespace x2car::camera
