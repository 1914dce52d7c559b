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

#include "x2car/core/camera_model.hpp"

namespace x2car::sim {

struct CameraOptions {
  // KITTI's rectified front camera, core::camera_preset("kitti"): 1242x375, fx = fy = 721.5 px
  // (~81 deg horizontal field of view), no distortion. Other presets: "automotive_1080p",
  // "dashcam_wide" (core/camera_model.hpp).
  core::CameraIntrinsics intrinsics = core::camera_preset("kitti");

  // Throws std::invalid_argument naming the offending field, also when some pixel of the image
  // has no ray (core::check_every_pixel_has_a_ray): the renderer traces one through each.
  void Check() const;
};

// R_B_O above: the optical frame's axes written in the camera's body frame.
Eigen::Matrix3d camera_body_from_optical();

// The optical frame's pose in the world for a vehicle pose and the camera's (body) mounting:
// world_from_vehicle * vehicle_from_camera * [R_B_O | 0]. A point p_world is seen at
// core::project_to_pixel(intrinsics, world_from_camera_optical(...).inverse() * p_world).
Eigen::Isometry3d world_from_camera_optical(const Eigen::Isometry3d& world_from_vehicle,
                                            const Eigen::Isometry3d& vehicle_from_camera);

}  // namespace x2car::sim
