// The simulated camera (DESIGN §4). What exists now is the sensor itself: its intrinsics and its
// mounting; the images are rendered from the same world in the camera issue.
//
// Frames (DESIGN §1, docs/conventions.md): the mounting `vehicle_from_camera` that the simulator
// draws and writes to ground_truth.yaml is that of the camera's body frame B (`camera_link`: x
// forward, y left, z up), as for every other sensor, so its roll, pitch and yaw read like theirs.
// The optical frame O (x right, y down, z forward), in which the intrinsics project, is
//   vehicle_from_camera_optical = vehicle_from_camera * [R_B_O | 0],
//   R_B_O = [[0, 0, 1], [-1, 0, 0], [0, -1, 0]]   (columns: O's axes in B).
#pragma once

#include <Eigen/Geometry>

#include "x2car/io/camera_intrinsics.hpp"

namespace x2car::sim {

struct CameraOptions {
  // 1920x1080, fx = fy = 1200 px (~77 deg horizontal field of view), principal point at the image
  // centre, no distortion: a common automotive front camera.
  io::CameraIntrinsics intrinsics;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// R_B_O above: the optical frame's axes written in the camera's body frame.
Eigen::Matrix3d camera_body_from_optical();

}  // namespace x2car::sim
