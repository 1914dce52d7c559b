// A recorded drive (`x2car simulate --trajectory FILE`): the route fitted to a recorded path's
// horizontal track, and where along it the car is at each recorded time, so that the simulated car
// drives that path at the recorded pace through a world generated around it.
//
// The route is the plan of route.hpp (curvature linear between knots every knot_spacing_m), found
// by driving along the path with a path-following controller in arc length: at each knot the
// curvature is the path's own (feed-forward) corrected by the cross-track error e and heading error
// de to the path (left and anticlockwise positive),
//   kappa = kappa_path - e / preview^2 - 2 zeta de / preview,     zeta = 0.7 (critically damped)
// so the route stays within centimetres of a smooth path; pose noise is smoothed over the
// preview length. The route is level (no grade or crossfall: the path's height is not followed)
// and starts at the ENU origin: the path is moved so that its first pose is there.
#pragma once

#include <span>
#include <vector>

#include "x2car/core/trajectory.hpp"
#include "x2car/sim/route.hpp"

namespace x2car::sim {

struct RecordedDriveOptions {
  double knot_spacing_m = 1.0;  // between the fitted route's curvature knots [m], [0.1, 100]
  double preview_m = 8.0;       // how fast the fit steers back onto the path [m], > 0
  double min_step_m = 0.02;     // poses closer than this to the last count as standing [m]
  double max_curvature = 0.2;   // the fit's curvature is clipped to this (R = 5 m) [1/m]
  double min_duration_s = 1.0;  // a recording must last at least this long [s]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct RecordedDrive {
  Route route;                      // along the path, from the ENU origin, level
  std::vector<double> times;        // of the poses, from 0 [s]
  std::vector<double> arc_lengths;  // of the poses along the route, non-decreasing [m]
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the first pose's position, subtracted [m]
};

// `poses` in a world whose z is up (ENU-like), times strictly increasing; only their positions
// are used (the car faces along the path). Throws std::invalid_argument for fewer than 2 poses, a
// recording shorter than min_duration_s or a path shorter than 1 m or longer than 1000 km.
RecordedDrive fit_recorded_drive(std::span<const StampedPose> poses,
                                 const RecordedDriveOptions& options = {});

// KITTI odometry poses are camera poses in the first camera's frame (x right, y down, z forward);
// this turns them into a z-up world: east = z, north = -x, up = -y.
std::vector<StampedPose> kitti_poses_to_z_up(std::span<const StampedPose> poses);

}  // namespace x2car::sim
