// Per-frame ground-truth labels of the simulated camera (issue 13, item 4; `camera/labels.csv`,
// docs/formats.md): what the camera calibrator (DESIGN §2, paper §III-A) measures in each image,
// computed exactly from the truth: the vanishing points (VP) of the car's forward axis and of the
// road's direction, and the horizon lines of the road plane and of the level plane.
//
// Frames: vehicle V at the frame time (VehicleState::world_from_vehicle, which holds the body's
// roll and pitch on its suspension), camera body B (`vehicle_from_camera`, DESIGN §1) and optical
// O = B * R_B_O (camera_body_from_optical()). A direction d in O has its VP at K d (pixels,
// homogeneous); a plane with upward unit normal n has its horizon (vanishing line) at
// l = K^-T n_O: the pixels whose rays are parallel to the plane.
//
// Pixels: "undistorted" pixels are those of the pinhole camera with the same K
// (core::undistort_pixel); "distorted" pixels are the image's own. The horizon is a straight line
// only in undistorted pixels (distortion bends it), so it is given only there.
//
// Horizon conventions (docs/conventions.md):
// - the homogeneous line (a, b, c) is scaled so that a^2 + b^2 = 1 and a u + b v + c is the signed
//   distance [undistorted px] of pixel (u, v) from the line, positive on the sky side (where the
//   plane's upward normal points; DESIGN §2: K^T l is then the up axis, y < 0 in O);
// - angle [rad]: of the line's direction (-b, a) against the image's u axis, counter-clockwise as
//   seen on screen (the right end higher is positive), in (-pi, pi]; a camera rolled by +r (left
//   side up, DESIGN §1) on a level car sees the level horizon at angle +r;
// - offset [px]: how far the line lies above the principal point, -(a cx + b cy + c): positive when
//   the camera looks below the horizon, as a camera pitched down (+pitch) does.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "x2car/core/camera_model.hpp"
#include "x2car/sim/road_layout.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

struct CameraLabelOptions {
  // "straight": the road's plan curvature stays below max_curvature over the next lookahead_m;
  // 2e-4 1/m (radius >= 5 km) bends a lane edge by < 0.25 m at 50 m, < 0.3 deg of VP direction.
  double lookahead_m = 50.0;    // [m], > 0
  double sample_step_m = 2.0;   // road sampled this often ahead of the car [m], > 0
  double max_curvature = 2e-4;  // [1/m], >= 0
  // "level": grade and crossfall each change by at most this over the next lookahead_m (0.005 m/m
  // = 0.29 deg: the road plane under the car is the road plane ahead).
  double max_grade_change = 0.005;      // [m/m], >= 0
  double max_crossfall_change = 0.005;  // [m/m], >= 0

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct HorizonLine {
  Eigen::Vector3d line = Eigen::Vector3d::Zero();  // (a, b, c), a^2 + b^2 = 1 (see above)
  double angle = 0.0;                              // [rad], counter-clockwise on screen
  double offset_px = 0.0;                          // above the principal point [undistorted px]
};

struct VanishingPoint {
  Eigen::Vector2d undistorted_px = Eigen::Vector2d::Zero();
  // In the image; nullopt outside the distortion model's domain (core::project_to_pixel).
  std::optional<Eigen::Vector2d> distorted_px;
};

struct CameraFrameLabel {
  double time = 0.0;       // [s], the frame's (VehicleState::time)
  double speed_mps = 0.0;  // signed, negative reversing [m/s]
  double yaw_rate = 0.0;   // [rad/s], positive turning left
  bool straight = false;   // the road ahead is straight (CameraLabelOptions)
  bool level = false;      // its grade and crossfall stay as under the car (CameraLabelOptions)
  // VPs of directions that point behind the camera (z <= 0 in O) are nullopt; horizons of planes
  // seen edge-on from above or below (normal along the optical axis) too.
  std::optional<VanishingPoint> forward_vp;  // of the car's x axis (fixed for a fixed mounting)
  std::optional<VanishingPoint> road_vp;     // of the road's tangent at the car, with its grade
  std::optional<HorizonLine> road_horizon;   // of the road surface's plane under the car
  std::optional<HorizonLine> level_horizon;  // of the level plane (normal: gravity, ENU z)
};

// The labels of one frame. `state` is the car at the frame time; `road` the world's road
// (World::road), read at the car's arc length. Pure; never NaN.
CameraFrameLabel camera_frame_label(const core::CameraIntrinsics& intrinsics,
                                    const Eigen::Isometry3d& vehicle_from_camera,
                                    const VehicleState& state, const RoadLayout& road,
                                    const CameraLabelOptions& options = {});

// The VP of a direction given in O, and the horizon of a plane with upward normal given in O:
// the two constructions above, for tests and for the calibrator's checks.
std::optional<VanishingPoint> vanishing_point(const core::CameraIntrinsics& intrinsics,
                                              const Eigen::Vector3d& direction_optical);
std::optional<HorizonLine> horizon_line(const core::CameraIntrinsics& intrinsics,
                                        const Eigen::Vector3d& up_normal_optical);

// `camera/labels.csv`: a header line, then one row per frame (docs/formats.md lists the columns).
// Numbers shortest-round-trip, flags 0/1, an absent VP or horizon as empty fields. Each ends in
// '\n'.
std::string format_camera_labels_csv_header();
std::string format_camera_label_row(const CameraFrameLabel& label);

}  // namespace x2car::sim
