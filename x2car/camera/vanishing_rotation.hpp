// Camera -> car rotation from one frame's vanishing point and horizon line, exactly (DESIGN §2,
// paper §III-A "Rotation Derivation", eq:camera_R3 and eq:camera_roll), and back.
//
// Frames (DESIGN §1): the optical frame O is x right, y down, z forward; the camera's body frame B
// (`camera_link`) is x forward, y left, z up, R_B_O = [[0,0,1],[-1,0,0],[0,-1,0]]; the mounting
// angles roll, pitch, yaw describe R_V_B = Rz(yaw) Ry(pitch) Rx(roll), and R_V_O = R_V_B R_B_O.
//
// The paper reads yaw and pitch off the ray of the vanishing point p (eq:camera_R3) and takes the
// roll as the horizon's angle in the image (eq:camera_roll), both small-angle readings. Here the
// whole rotation is built from the two directions they give and then split into Euler angles:
//   f = normalize(K^-1 p)                  the car's x axis (forward) in O, z > 0;
//   u = normalize(K^T l)                   the car's z axis (up) in O: the normal of the plane
//                                          through the camera centre and the horizon line l,
//                                          signed to point up (y < 0 in O);
//   u <- normalize(u - (u . f) f)          the horizon gives only the roll: the vanishing point
//                                          keeps pitch and yaw;
//   R_O_V = [f, u x f, u]                  the car's axes (columns) in O;
//   R_V_B = R_O_V^T R_B_O^T.
//
// Image coordinates are undistorted pixels (u right, v down, OpenCV: (0, 0) the centre of the
// top-left pixel); a horizon line is homogeneous, a u + b v + c = 0.
//
// What the signs look like in the image (the DESIGN §1 checks, tested in the _test file):
//   - a camera pitched down (+pitch) sees the vanishing point above the principal point (v < cy);
//   - a camera yawed left (+yaw) sees it right of the principal point (u > cx);
//   - a camera rolled left side up (+roll) sees the horizon rise to the right: its angle, counted
//     counter-clockwise as a person looks at the image (horizon_angle below), is +roll for a level
//     camera. Roll the other way, the horizon falls to the right.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "x2car/core/rotation.hpp"

namespace x2car::camera {

// The image of the car's forward direction and of the level plane, in undistorted pixels.
struct VanishingGeometry {
  Eigen::Vector2d vanishing_point_px = Eigen::Vector2d::Zero();  // of the car's x axis
  // The horizon a u + b v + c = 0, scaled so that a^2 + b^2 = 1 and b > 0 (b < 0 only for a
  // horizon steeper than vertical, which no mounting of this module's range gives).
  Eigen::Vector3d horizon_line = Eigen::Vector3d(0.0, 1.0, 0.0);
};

// R_V_B of the camera's body frame (DESIGN §1) from the vanishing point of the car's forward
// direction and the horizon line (formulas above). nullopt when the geometry is degenerate: a
// non-finite input, a horizon line with a = b = c = 0, or a horizon whose plane normal is parallel
// to the forward ray (no roll can be read).
std::optional<Eigen::Matrix3d> vehicle_from_camera_rotation(
    const Eigen::Vector2d& vanishing_point_px, const Eigen::Vector3d& horizon_line,
    const Eigen::Matrix3d& camera_matrix);

// The same as mounting angles (roll, pitch, yaw of R_V_B) [rad].
std::optional<EulerAngles> vehicle_from_camera_angles(const Eigen::Vector2d& vanishing_point_px,
                                                      const Eigen::Vector3d& horizon_line,
                                                      const Eigen::Matrix3d& camera_matrix);

// The car's axes in O: R_O_V from the forward ray f and the up direction u, both in O, any length
// (the steps above after K^-1 and K^T). nullopt when either is zero or non-finite, or when they
// are parallel.
std::optional<Eigen::Matrix3d> optical_from_vehicle(const Eigen::Vector3d& forward_in_optical,
                                                    const Eigen::Vector3d& up_in_optical);

// R_B_O of DESIGN §1: the optical frame's axes (x right, y down, z forward; columns) in the
// camera's body frame (x forward, y left, z up).
Eigen::Matrix3d body_from_optical();

// R_V_B from R_O_V: R_V_B = R_O_V^T R_B_O^T.
Eigen::Matrix3d vehicle_from_camera_body(const Eigen::Matrix3d& optical_from_vehicle);

// The inverse: where a camera mounted with R_V_B sees the car's forward vanishing point and the
// horizon of the car's x-y plane. nullopt when the forward direction is not in front of the camera
// (z <= 0 in O: a camera turned 90 deg or more away).
std::optional<VanishingGeometry> vanishing_geometry_from_rotation(
    const Eigen::Matrix3d& vehicle_from_camera, const Eigen::Matrix3d& camera_matrix);

// The horizon line whose plane has the normal `up_in_optical` (the polar line K^-T u), normalised
// as VanishingGeometry::horizon_line. nullopt for a zero or non-finite direction, or one along the
// optical axis (its horizon lies at infinity).
std::optional<Eigen::Vector3d> horizon_from_up(const Eigen::Vector3d& up_in_optical,
                                               const Eigen::Matrix3d& camera_matrix);

// The horizon's angle in the image [rad], counter-clockwise as a person looks at the image (v up):
// positive when it rises to the right. In (-pi/2, pi/2].
double horizon_angle(const Eigen::Vector3d& horizon_line);

}  // namespace x2car::camera
