// LiDAR -> car: roll, pitch and height from the ground plane, yaw from the odometry's track
// (DESIGN §2, paper §III-B).
//
// One pass over the sweeps: they are read and, every `ground_every`-th, their ground plane fitted
// in parallel, while the odometry registers them in order (a oneTBB pipeline), so a long log never
// sits in memory. Then:
//   - the ground planes of frames where the car is not turning give roll, pitch and height (roll
//     and height their medians, so that the body's lean in left and right turns, braking and
//     speeding up averages out; the pitch with the lean fitted out against the acceleration);
//   - the odometry poses are levelled with that roll and pitch and handed to the track alignment
//     shared with the GNSS/INS calibrator (core/track_alignment.hpp): the heading of the
//     spline-smoothed track against the levelled LiDAR's heading gives the yaw (the paper's
//     eq:lidar_angle), and the direction of the velocity in the levelled frame gives an independent
//     yaw and pitch (non-holonomic cross-check). Disagreements are reported.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/track_alignment.hpp"
#include "x2car/core/yaw_choice.hpp"
#include "x2car/io/point_cloud.hpp"
#include "x2car/lidar/ground.hpp"
#include "x2car/lidar/odometry.hpp"
#include "x2car/lidar/sweep_folder.hpp"

namespace x2car::lidar {

// Errors of the ground's roll, pitch and height that stay with a drive and that no spread of the
// frames shows, added in quadrature to their standard errors (docs/methods.md, "Ground plane").
struct GroundBias {
  // The fitted patch 3-15 m around the LiDAR is not exactly the plane the wheels stand on: rutting,
  // patches, the road's unevenness of a few millimetres over metres that road standards tolerate.
  double roll = rad_from_deg(0.01);   // [rad], 1 sigma
  double pitch = rad_from_deg(0.01);  // [rad], 1 sigma
  double height_m = 0.002;            // [m], 1 sigma
  // The body leans on its suspension: the median cancels it only when the drive's accelerations
  // balance. Each frame's expected lean (its acceleration from the odometry times the lean per
  // acceleration) is taken out of the spread, and the shift of the median it explains is added.
  // Defaults in the middle of passenger cars' range (pitch 1.5-3.5 deg/g under braking and
  // acceleration, roll 3-7 deg/g): 0.3 deg and 0.5 deg per m/s^2. A height error follows the
  // pitch by the LiDAR's distance from the point the body pitches about (a roof LiDAR: ~1.5 m).
  double pitch_per_acceleration = rad_from_deg(0.3);  // [rad / (m/s^2)]
  // The pitch's lean is fitted, not only bounded: the gain above is the prior's mean and this its
  // standard deviation (the passenger-car range 0.15-0.36 deg per m/s^2 and softer suspensions);
  // the frames refine it where the drive brakes and speeds up (docs/methods.md, "Ground plane").
  double pitch_per_acceleration_std = rad_from_deg(0.15);    // [rad / (m/s^2)], > 0
  double roll_per_lateral_acceleration = rad_from_deg(0.5);  // [rad / (m/s^2)]
  double height_per_pitch_m = 1.5;                           // [m / rad]

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct LidarCalibrationOptions {
  OdometryOptions odometry;
  GroundOptions ground;
  // The ground plane is fitted on every k-th sweep: neighbouring sweeps see nearly the same road,
  // so more frames add time, not information.
  int ground_every = 2;
  // Frames turning faster than this (the odometry's angular rate) are not used for the ground
  // [rad/s]: the body rolls on its suspension in proportion to the lateral acceleration.
  double max_ground_turn_rate = 0.05;
  // Per-frame outliers (a passing truck taken for the road, a ramp) are rejected by median/MAD.
  OutlierRejectionOptions ground_outliers{.k = 3.0, .min_sigma = rad_from_deg(0.01)};
  // The road under a standing LiDAR does not change: when the odometry has the car below
  // standing_speed in more than half the ground frames and their roll or pitch still spreads
  // (interquartile range) more than max_standing_ground_spread, the odometry lost the motion and
  // the result is unreliable. A car settling after a stop moves its pitch by a few tenths of a
  // degree for a second; a half-minute's standing frames are well inside the limit.
  double standing_speed = 0.5;                            // [m/s]
  double max_standing_ground_spread = rad_from_deg(0.2);  // [rad]
  // Standard errors come from the spread of means over moving blocks this long [s]
  // (core/standard_error.hpp): neighbouring frames see the same stretch of road and are not
  // independent (the road's unevenness over tens of metres; the body's lean, whose expected part
  // is taken out of the spread, see GroundBias).
  double block_s = 5.0;
  // Floor of the roll's, pitch's and height's standard errors.
  GroundBias ground_bias;
  // Spline, gates and averaging of the yaw; see core/track_alignment.hpp.
  TrackAlignmentOptions alignment;
  // Which yaw the result reports (both are always computed and kept in the diagnostics).
  YawMethod yaw_method = YawMethod::kAuto;
  // The ground's sideways limit (GroundOptions::max_lateral_m) is measured across the way the car
  // drives, which calibrate_lidar takes from the odometry's track (so it sets
  // ground.travel_yaw itself): the steps faster than standing_speed, their directions in the
  // LiDAR's xy plane averaged as axes and weighted by their length. Until the track has covered
  // this much [m] the axis is not known; those sweeps' ground is fitted again after the pass with
  // the whole track's axis (with the LiDAR's x axis when the car never covered it).
  double travel_axis_distance_m = 10.0;
  // Fewer sweeps than this, or fewer usable ground frames, is insufficient data.
  std::size_t min_sweeps = 20;
  std::size_t min_ground_frames = 10;
  // More failed registrations than this share of the sweeps makes the yaw untrustworthy.
  double max_failed_registration_share = 0.05;
  // The two yaws, and the ground's pitch against the motion's, are cross-checks of each other:
  // disagreements are reported in `reason`.
  DisagreementTest disagreement;
  bool keep_series = true;  // per-frame ground normals, heights and heading offsets
  std::uint64_t seed = 1;   // of the ground's RANSAC
  // A sweep whose `read` throws InputError (a truncated or corrupt file) is skipped and counted
  // (rejections["unreadable_sweep"], the first message in `reason`); the odometry continues from
  // the next sweep. Off: the InputError ends the run.
  bool skip_bad_sweeps = false;
  // Called after each sweep has passed the odometry (in order, from one thread at a time) with the
  // sweeps done and the total, e.g. for a progress bar; empty: not called. Must not throw.
  std::function<void(std::size_t done, std::size_t total)> progress;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The sweeps of a log: their times and how to read each. `read` is called from several threads at
// once (each index once) and may throw InputError.
struct SweepSource {
  std::vector<double> times;  // [s], strictly increasing
  std::function<io::PointCloud(std::size_t index)> read;
};

SweepSource sweep_source_from(const SweepFolder& folder);

// Returns an ok result, or insufficient_data with a reason that says what is missing; never NaN
// angles. Roll, pitch and z are reported whenever the ground allows, also when the yaw lacks data
// (status insufficient_data, the reason saying why). InputError from `read` passes through unless
// skip_bad_sweeps; std::invalid_argument on invalid options.
CalibrationResult calibrate_lidar(const SweepSource& sweeps,
                                  const LidarCalibrationOptions& options = {});

}  // namespace x2car::lidar
