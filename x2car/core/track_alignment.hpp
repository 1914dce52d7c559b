// How a sensor's attitude lines up with the direction the car moves (DESIGN §2, paper §III-C).
// Shared by every calibrator that has the sensor's pose over time (GNSS/INS from the device,
// LiDAR from its odometry).
//
// Track-heading method (the paper's eq:IMU_angle / eq:lidar_angle; core/track_heading.hpp): fit
// x(t), y(t) with a P-spline, take the heading of its tangent, keep the moving, nearly straight
// samples (segment_runs), and compare with the sensor's yaw at the same timestamp: offset =
// wrap(sensor yaw - track heading). On a level car the sensor's ZYX yaw is the car's heading plus
// the mounting yaw exactly, so the offset is the mounting yaw.
//
// Velocity-direction method (beyond the paper): a car does not slide sideways or lift off, so its
// velocity points along its x axis (non-holonomic constraint). With the car frame V0 built from
// the velocity (x along it, y horizontal, z up), the sensor's x axis expressed in V0 gives
//   yaw   = atan2(x_S . y_V0, x_S . x_V0),   pitch = -asin(x_S . z_V0),
// the ZYX yaw and pitch of vehicle_from_sensor. Roll would need the car's own roll in the world
// (crossfall, body roll), which nothing here observes.
//
// Turns (beyond the paper; core/turn_geometry.hpp): by default the samples in turns are kept where
// the lateral acceleration is low (sideslip small), and the sensor's lever arm ahead of the rear
// axle, which turns its track by beta = asin(kappa r_x) against the car's, is added back: the given
// one, or r_x fitted jointly with the yaw. When r_x cannot be identified (the curvature hardly
// varies, or the fit gives a lever arm no car has), the paper's straight-only gates are used.
// TurnSamples::kExclude keeps the paper's method (with a given lever arm still corrected for).
//
// Samples where the car reverses are found as those whose offset is more than 90 deg from the
// circular mean offset of all moving samples, and excluded.
//
// The track is first split where the time between two samples exceeds split_gap_s (a logger
// pause, a jump in the time stamps) and each piece is smoothed on its own: a spline across the gap
// would invent a path there and cost time and memory in proportion to the gap, not to the data.
// Pieces too short to hold a run are left out and counted.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/planar_track.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/segment_average.hpp"
#include "x2car/core/segmentation.hpp"
#include "x2car/core/turn_geometry.hpp"

namespace x2car {

// A sensor's pose over time in a local ENU world, one entry per sample.
struct SensorTrack {
  std::vector<double> time;                   // [s], strictly increasing
  std::vector<Eigen::Vector3d> position_enu;  // of the sensor [m]
  std::vector<Eigen::Matrix3d> world_from_sensor;
  // Of the sensor [m/s]; empty: taken from the spline of the positions.
  std::vector<Eigen::Vector3d> velocity_enu;
};

// Where the curvature that gates out turns comes from.
enum class TurnGate {
  // The sensor's yaw rate (a P-spline of its unwrapped heading) over the track's speed. The
  // attitude of an INS or of LiDAR odometry is far less noisy than a GNSS track's second
  // derivative: with metre-level position noise the track's curvature rejects most straights.
  kSensorYawRate,
  kTrackCurvature,  // the paper's: the curvature of the smoothed track
};

// Whether the samples in turns are used.
enum class TurnSamples {
  kUse,      // kept up to TurnOptions::max_lateral_acceleration, corrected for the lever arm
  kExclude,  // the paper's: only |curvature| <= segments.max_abs_curvature
};

std::string to_string(TurnSamples turns);  // "use", "exclude"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
TurnSamples turn_samples_from_string(std::string_view name);
std::vector<std::string> turn_samples_names();

struct TurnOptions {
  TurnSamples samples = TurnSamples::kUse;
  // [m/s^2] samples turning with a larger lateral acceleration (speed x yaw rate) are not used.
  // A car's tyres slip sideways in proportion to it: at the rear axle about 0.2-0.5 deg per m/s^2
  // (the rear axle's load over its cornering stiffness), which the lever-arm model leaves out. At
  // <= 2 m/s^2 that is <= ~1 deg in a single sample, of opposite sign in left and right turns, and
  // it is what ordinary urban turns at 15-25 km/h reach (a 20 m radius at 6 m/s: 1.8 m/s^2).
  double max_lateral_acceleration = 2.0;
  // [1/m] a sanity bound: sharper than a 5 m radius is a manoeuvre, not a road.
  double max_abs_curvature = 0.2;
  // [s] trimmed off each end of a run. The paper's 1 s (segments.end_trim_s) is where a turn fades
  // in or out; with turns used the runs end where the car slows below min_speed or the lateral
  // acceleration passes the gate, where the heading needs no margin.
  double end_trim_s = 0.0;
  // [s] the shortest run kept (the paper's 5 s, segments.min_duration_s, makes sure a run is a
  // straight): with turns used, the runs between a stop and a sharp corner are short and sound.
  double min_run_s = 2.0;
  // The sensor's position in the vehicle frame [m] (x forward of the rear axle); only x is used.
  // Unset: x is estimated from the turns.
  std::optional<Eigen::Vector3d> lever_arm;
  LeverArmFitOptions fit;
  // The estimated lever arm is used only when the curvature's standard deviation over the valid
  // samples is at least min_curvature_spread [1/m] (on a circle, or on a highway's gentle curves,
  // the turns cannot separate x from the yaw, and add little the paper's gates do not keep) ...
  double min_curvature_spread = 0.002;
  // ... when |x| <= max_abs_lever_arm_x [m] (a larger one means
  // the model does not hold: sideslip, velocities in another frame) ...
  double max_abs_lever_arm_x = 6.0;
  // ... and when the yaw's uncertainty from it, |mean curvature| x SE(x), is at most this [rad]:
  // on a drive that turns mostly one way the yaw and x are hard to tell apart. That uncertainty is
  // added to the yaw's standard error; beyond a twentieth of a degree the turns cost more than
  // they give.
  double max_lever_arm_yaw_std = rad_from_deg(0.05);

  void Check() const;
};

struct TrackAlignmentOptions {
  PlanarTrackOptions track;  // x(t), y(t) smoother; z(t) and the heading use the same options
  TurnGate turn_gate = TurnGate::kSensorYawRate;
  // The paper's gates: speed >= 3 m/s, |curvature| <= 0.01 1/m, runs of at least 5 s. A second is
  // trimmed off each run's ends, where a turn's heading rate fades in or out.
  SegmentationOptions segments{.min_speed = 3.0,
                               .max_abs_curvature = 0.01,
                               .min_duration_s = 5.0,
                               .max_gap_s = 0.5,
                               .end_trim_s = 1.0};
  // Samples in turns: used (default) or excluded (the paper's gates above).
  TurnOptions turns;
  SegmentAverageOptions average;
  // A car's body pitches on its suspension when it speeds up or brakes, so the velocity leaves its
  // x axis by an angle proportional to the longitudinal acceleration. When set, the per-sample
  // pitch is regressed on that acceleration and the fitted share removed before averaging.
  bool remove_body_pitch = true;
  // The regression is skipped when the acceleration varies less than this [m/s^2] (std).
  double min_acceleration_spread = 0.05;
  // Less valid driving than this (summed over the segments) is insufficient data [s].
  double min_valid_duration_s = 20.0;
  // Samples slower than this are not tested for reversing (their direction is noise) [m/s].
  double reversing_test_min_speed = 0.5;
  // A gap between samples longer than this splits the track into pieces smoothed separately [s].
  // Longer than any dropout a spline should bridge; runs already break at segments.max_gap_s.
  double split_gap_s = 2.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct TrackAlignment {
  // Per sample (all samples of the input, in order).
  PlanarTrackSamples track;                // smoothed track: speed, heading_enu, curvature
  std::vector<double> gate_curvature;      // what the turn gate tested [1/m]
  std::vector<double> yaw_rate_curvature;  // the sensor's yaw rate over its speed [1/m]
  std::vector<double> sensor_heading;      // ZYX yaw of world_from_sensor [rad]
  // wrap(sensor_heading - track heading + lever_arm_shift) [rad]
  std::vector<double> heading_offset;
  // Per-sample yaw of the velocity method, + lever_arm_shift [rad].
  std::vector<double> velocity_yaw;
  // beta = asin(yaw_rate_curvature * lever_arm_x), added to both yaws [rad]; all 0 without a lever
  // arm.
  std::vector<double> lever_arm_shift;
  std::vector<double> velocity_pitch;  // per-sample pitch of the velocity method [rad]
  // Per-sample angle of the velocity above the sensor's xy plane, asin(v . z_sensor) [rad]: it
  // needs no level world, only the sensor's frame. For a sensor facing ahead it is its pitch,
  // facing sideways its roll; it is 0 for any yaw when the sensor's xy plane is the car's (a
  // levelled sensor: the check of a ground plane's roll and pitch against the motion).
  std::vector<double> velocity_elevation;
  std::vector<double> longitudinal_acceleration;  // of the smoothed track [m/s^2]
  // Fitted body pitch per longitudinal acceleration, removed from velocity_pitch_estimate
  // [rad / (m/s^2)]; 0 when not fitted. Braking (a < 0) dips the nose (pitch > 0): usually < 0.
  double pitch_per_acceleration = 0.0;
  std::vector<std::uint8_t> reversing;  // 1 where the car moved backwards
  std::int64_t reversing_samples = 0;   // how many
  // Samples not reversing but with a zero or vertical velocity (no direction to compare with).
  std::int64_t without_direction = 0;
  bool velocity_from_sensor = false;  // the input's velocities were used (else the spline's)

  // Turns: whether their samples were used, the lever arm x [m] the yaws were corrected for, and
  // the fit when it was estimated (its standard error is added to the yaws').
  bool turns_used = false;
  double lever_arm_x = 0.0;
  std::optional<LeverArmFit> lever_arm_fit;
  // Set when the lever arm was fitted but could not be used (turns then excluded): why.
  std::optional<std::string> lever_arm_rejected;

  // The pieces between time gaps longer than split_gap_s: smoothed, and left out for being shorter
  // than segments.min_duration_s or having too few samples for the spline. The samples of the
  // short pieces are NaN in the per-sample vectors above (speed 0) and counted here.
  std::int64_t pieces = 0;
  std::int64_t short_pieces = 0;
  std::int64_t in_short_pieces = 0;

  // rejections.excluded counts the reversing samples, those without a direction and those in
  // short pieces.
  Segmentation segmentation;
  double valid_duration_s = 0.0;

  // Set when there is too little valid driving; then the estimates below are empty.
  std::optional<std::string> insufficient_reason;
  std::optional<SegmentAverage> yaw;                      // track-heading method
  std::optional<SegmentAverage> velocity_yaw_estimate;    // velocity-direction method
  std::optional<SegmentAverage> velocity_pitch_estimate;  // velocity-direction method
  // The mean of velocity_elevation, its body pitch removed like the pitch's (its own slope).
  std::optional<SegmentAverage> velocity_elevation_estimate;
};

// A track too short or too sparse gives insufficient_reason, not an exception. Throws
// std::invalid_argument when the track's vectors differ in length or times do not strictly increase
// (readers check this with a better message), or on invalid options.
TrackAlignment align_track(const SensorTrack& sensor_track,
                           const TrackAlignmentOptions& options = {});

}  // namespace x2car
