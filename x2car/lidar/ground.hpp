// The road plane under a LiDAR from one sweep (paper §III-B, DESIGN §2): the road's normal in
// LiDAR coordinates gives the LiDAR's roll and pitch to a frame whose z axis is that normal, and
// the plane's offset gives the LiDAR's height above the road.
//
// Method, in the paper's steps:
//   1. range filter: points with a horizontal distance in [min_range_m, max_range_m], within
//      max_lateral_m sideways of the car's travel (travel_yaw), and low enough to be road under a
//      LiDAR mounted min_height_m .. max_height_m above it and tilted at most max_tilt (walls, cars
//      and trees above the road are dropped before any fit); NaN/inf points are skipped and
//      counted;
//   2. multi-start RANSAC on a seeded random subsample of those points: each start draws its own
//      seeded stream of 3-point planes and keeps the best by the MSAC score (truncated squared
//      distance), planes tilted beyond max_tilt are never considered;
//   3. random search around the best plane: perturb its normal and offset by shrinking random
//      steps and keep every step that lowers the score;
//   4. least-squares refit (smallest eigenvector of the inliers' covariance, which is the SVD of
//      the centred inliers) over all filtered points near the plane, repeated with a band that
//      tightens to a multiple of the fit's RMS distance.
// The normal is turned to point up (towards the LiDAR), so the plane is n . p = -height_m.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/io/point_cloud.hpp"

namespace x2car::lidar {

struct GroundOptions {
  // Range filter, horizontal distance sqrt(x^2 + y^2) in the LiDAR frame [m]. Near points may be
  // the car's own body; far ones bend away with the road's vertical curves (the simulator's
  // grade changes by up to ~1e-3 per metre, which at 30 m is 0.45 m of sag): the plane's offset
  // then drifts by about -25 m x (grade change per metre) at 20 m, so the default keeps the road
  // close to the car (bench/ground_study.cpp: 10-15 m give the smallest height errors).
  double min_range_m = 3.0;
  double max_range_m = 15.0;
  // Points farther than this sideways (|y| in the LiDAR frame) are dropped [m]: keeps the fit on
  // the carriageway, away from curbs, sidewalks and parked cars (in the simulator's urban road
  // the right curb is 3.75 m from the car's path; at 4 m the curb's foot tilts roll by ~0.03 deg).
  // <= 0 turns the limit off.
  double max_lateral_m = 3.0;
  // The way the car drives, as an angle in the LiDAR's xy plane from its x axis about its z axis
  // [rad]: max_lateral_m is measured across it. 0 takes the LiDAR's x axis as the car's; the
  // calibration sets it from the odometry's track (calibrate_lidar), since a LiDAR mounted at a yaw
  // of 90 deg has the road's width along its x axis, and a strip along it would hold the curbs and
  // sidewalks beside the car. Only the axis counts: 180 deg more is the same strip.
  double travel_yaw = 0.0;
  // Height prior of the LiDAR above the road [m]: a candidate must lie between min_height_m and
  // max_height_m below the LiDAR, widened by r * tan(max_tilt) at horizontal distance r.
  double min_height_m = 0.3;
  double max_height_m = 4.0;
  // Largest angle between the road's normal and the LiDAR's z axis [rad]: mounting tilt plus
  // road grade and crossfall plus body roll and pitch. Planes tilted more are rejected.
  double max_tilt = rad_from_deg(12.0);

  // RANSAC scores planes against at most this many filtered points, drawn at random (seeded):
  // a fixed stride could line up with the beams' order.
  std::size_t max_candidates = 2048;
  int ransac_starts = 4;          // independent RANSAC runs, each with its own seeded stream
  int ransac_iterations = 24;     // 3-point planes drawn per start
  double ransac_inlier_m = 0.10;  // MSAC truncation distance [m]

  // Random search around the best RANSAC plane: refine_steps perturbations, with the normal
  // turned by a random angle ~ N(0, scale) about a random horizontal axis and the offset moved by
  // N(0, scale); the scales shrink geometrically from the initial ones to refine_final_fraction of
  // them.
  int refine_steps = 48;
  double refine_angle = rad_from_deg(1.0);  // initial angle scale [rad]
  double refine_offset_m = 0.05;            // initial offset scale [m]
  double refine_final_fraction = 0.02;      // final scale / initial scale, (0, 1]

  // Least-squares refit over all filtered points near the plane, repeated refit_passes times, each
  // pass selecting the inliers of the previous pass's plane: the first within refit_inlier_m [m],
  // the later ones within refit_rms_factor x the previous pass's RMS distance, clamped to
  // [min_refit_inlier_m, refit_inlier_m]. The tighter band adapts to the sensor's noise and keeps
  // out the feet of walls, hedges and curbs, whose lowest points would otherwise tilt the plane.
  double refit_inlier_m = 0.05;
  double min_refit_inlier_m = 0.02;
  double refit_rms_factor = 3.0;
  int refit_passes = 3;

  // A fit needs at least this many filtered points and final inliers, and at least
  // min_inlier_fraction of the filtered points among its final inliers.
  std::size_t min_inliers = 300;
  double min_inlier_fraction = 0.3;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct GroundPlane {
  // Unit normal of the road in LiDAR coordinates, pointing up (away from the road, towards the
  // LiDAR): the road plane is { p : normal_in_lidar . p + height_m = 0 }.
  Eigen::Vector3d normal_in_lidar = Eigen::Vector3d::UnitZ();
  double height_m = 0.0;       // distance from the LiDAR origin to the plane [m], > 0
  std::size_t inliers = 0;     // filtered points used in the last refit pass
  std::size_t candidates = 0;  // points that passed the range and height filter
  double rms_m = 0.0;          // RMS distance of the inliers from the plane [m]
};

struct GroundFit {
  std::optional<GroundPlane> plane;  // empty when no plane was found
  std::string failure;               // why not, when `plane` is empty
  std::size_t invalid_points = 0;    // NaN/inf points skipped
};

// Working memory of fit_ground, reusable between calls so that a loop over sweeps allocates
// nothing once the buffers have grown. One per thread; the contents between calls mean nothing.
struct GroundScratch {
  std::vector<Eigen::Vector3f> filtered;    // points that passed the filter
  std::vector<Eigen::Vector3f> candidates;  // the RANSAC subsample of them
};

// Fits the road plane in one sweep. Pure: the same sweep, options and seed give the same plane.
// Throws std::invalid_argument on bad options; too few or unusable points give a GroundFit with a
// failure, never an exception.
GroundFit fit_ground(const io::PointCloud& sweep, const GroundOptions& options, std::uint64_t seed);
GroundFit fit_ground(const io::PointCloud& sweep, const GroundOptions& options, std::uint64_t seed,
                     GroundScratch& scratch);

// Mounting angles of the LiDAR relative to a frame whose z axis is the road's normal (DESIGN §2,
// docs/conventions.md): for R_V_L = Rz(yaw) Ry(pitch) Rx(roll), the normal e_z of V in LiDAR
// coordinates is the last row of R_V_L, (-sin pitch, cos pitch sin roll, cos pitch cos roll), so
// exactly and for any yaw:
double roll_from_ground(const Eigen::Vector3d& normal_in_lidar);   // atan2(n_y, n_z) [rad]
double pitch_from_ground(const Eigen::Vector3d& normal_in_lidar);  // asin(-n_x) [rad]

}  // namespace x2car::lidar
