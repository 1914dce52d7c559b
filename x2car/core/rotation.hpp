// Rotations and angles in the conventions of docs/conventions.md.
//
// Mounting angles are intrinsic Z-Y'-X'' Euler angles:
//   R_V_S = Rz(yaw) * Ry(pitch) * Rx(roll)      (tf2 setRPY, Autoware sensor_kit_calibration.yaml)
// Positive yaw turns the sensor's x axis to the left, positive pitch tilts it down, positive roll
// lowers the sensor's right side (its y axis rises). All angles are radians.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <span>

namespace x2car {

// Roll, pitch and yaw [rad] of R = Rz(yaw) * Ry(pitch) * Rx(roll).
struct EulerAngles {
  double roll = 0.0;   // about x [rad]
  double pitch = 0.0;  // about y [rad]
  double yaw = 0.0;    // about z [rad]
};

Eigen::Matrix3d rotation_from_euler(const EulerAngles& angles);

// Inverse of rotation_from_euler. Pitch is in [-pi/2, pi/2]; roll and yaw in (-pi, pi]. At gimbal
// lock (|pitch| = pi/2) only yaw - roll (pitch > 0) or yaw + roll (pitch < 0) is defined; roll is
// then reported as 0 and the whole rotation goes into yaw, so the round trip still holds.
EulerAngles euler_from_rotation(const Eigen::Matrix3d& rotation);

Eigen::Quaterniond quaternion_from_euler(const EulerAngles& angles);
EulerAngles euler_from_quaternion(const Eigen::Quaterniond& quaternion);

// Rotation vector (axis * angle [rad]) and back; the angle of the vector lies in [0, pi].
Eigen::Vector3d rotation_vector_from_rotation(const Eigen::Matrix3d& rotation);
Eigen::Matrix3d rotation_from_rotation_vector(const Eigen::Vector3d& rotation_vector);

// Angle [rad] of the rotation that takes a onto b, in [0, pi].
double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

// The unit vector of the plane at `angle` [rad] from the x axis, counter-clockwise.
inline Eigen::Vector2d unit_vector(double angle) { return {std::cos(angle), std::sin(angle)}; }

// The nearest rotation matrix (in the Frobenius sense) to an almost-orthonormal 3x3 matrix.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& matrix);

// True when the matrix is a rotation within tolerance: orthonormal and determinant +1.
bool is_rotation(const Eigen::Matrix3d& matrix, double tolerance = 1e-6);

// Builds a rigid transform target_from_source from a rotation and a translation [m].
Eigen::Isometry3d make_transform(const Eigen::Matrix3d& rotation,
                                 const Eigen::Vector3d& translation);
Eigen::Isometry3d make_transform(const EulerAngles& angles, const Eigen::Vector3d& translation);

// ---- plain angles -------------------------------------------------------------------------

constexpr double kPi = 3.14159265358979323846;

constexpr double deg_from_rad(double radians) { return radians * (180.0 / kPi); }
constexpr double rad_from_deg(double degrees) { return degrees * (kPi / 180.0); }

// Wraps an angle [rad] to (-pi, pi].
double wrap_angle(double angle);

// The signed difference a - b wrapped to (-pi, pi] [rad]: how far b must turn to reach a.
double angle_difference(double a, double b);

// Mean direction of angles [rad] on the circle, in (-pi, pi]; weights are optional (empty = all
// 1). Throws std::invalid_argument when the input is empty, sizes differ, a weight is negative, or
// the resultant vanishes (the directions cancel out and no mean exists).
double circular_mean(std::span<const double> angles, std::span<const double> weights = {});

// Mean resultant length in [0, 1]: 1 when all angles agree, near 0 when they spread around.
double mean_resultant_length(std::span<const double> angles, std::span<const double> weights = {});

// The end that most angles [rad] lie within 90 deg of, of the axis they gather round (the circular
// mean of the doubled angles, halved), in (-pi, pi]: of the offsets between a car's course and a
// device's heading, the one it has driving ahead when most of a drive goes forward (backing up
// falls at the axis' other end, whatever share it has). nullopt when there are none, or when the
// doubled angles' mean resultant length is below `min_agreement` or vanishes (no axis at all).
std::optional<double> majority_axis_end(std::span<const double> angles, double min_agreement);

// ---- conversions between the reported azimuth and the ENU heading -------------------------

// Azimuth is clockwise from north (NovAtel, OxTS); ENU heading is counter-clockwise from east.
// Both [rad]; the result is wrapped to (-pi, pi].
double heading_enu_from_azimuth(double azimuth);
double azimuth_from_heading_enu(double heading_enu);

}  // namespace x2car
