// The radar's own motion at each detection, from the GNSS/INS log (DESIGN §2, paper §III-D).
//
// The INS is mounted on the car with a yaw that is not known here, so its attitude cannot give the
// car's heading. What it does give, independent of its mounting:
//   - the car's speed: the INS velocity's norm; by the non-holonomic constraint the car
//     moves along its own x axis, so v_car_in_vehicle = (s, 0) with s > 0 forward, s < 0 when the
//     velocity points more than 90 deg away from the way the car drives in most of the log,
//     against the INS heading (reversing): the INS's mounting yaw may be any (180 deg for a box
//     mounted backwards), and most of a drive goes forward;
//   - the yaw rate omega [rad/s], d(INS yaw)/dt, the same for every point of the rigid car; the
//     slope of a least-squares line through the INS yaw over yaw_rate_window_s, since the
//     heading's white noise makes differences of neighbouring records far too noisy.
// The lever arm between the INS and the car's origin is neglected (its effect on the speed is
// omega times a lever arm of a metre or so, only in turns).
//
// The radar's velocity over ground in the vehicle frame V:
//   with its lever arm t_V_R = (x_r, y_r) given:  v_radar = (s - omega y_r, omega x_r)
//   without:                                       v_radar = (s, 0), exact only when omega = 0
// and the calibrator gates out turns in the second case. The radar's mounting yaw psi found from
// these is the yaw relative to the car's direction of motion, i.e. to the vehicle x axis.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "x2car/io/ins_csv.hpp"
#include "x2car/io/ins_log.hpp"
#include "x2car/io/radar_csv.hpp"

namespace x2car::radar {

// One detection with the radar's motion when it was taken.
struct RadarSample {
  double time = 0.0;  // [s] on the GNSS/INS log's clock
  int track_id = io::kNoTrackId;
  bool new_track = false;      // the radar's first report of this track (io::RadarDetection)
  double range = 0.0;          // [m]
  double azimuth = 0.0;        // in the radar frame, counter-clockwise positive [rad]
  double range_rate = 0.0;     // negative approaching [m/s]
  double car_speed_mps = 0.0;  // signed speed of the car along its x axis [m/s]
  double yaw_rate = 0.0;       // of the car, positive turning left [rad/s]
  // The radar's velocity over ground in the vehicle frame [m/s].
  Eigen::Vector2d radar_velocity_in_vehicle = Eigen::Vector2d::Zero();
  // For the position method: the INS yaw unwrapped over the whole log [rad], and the car's path by
  // dead reckoning, odometry(t) = integral of speed * (cos, sin)(INS yaw) dt [m]. The INS's
  // mounting yaw beta is unknown, so both live in a frame turned by beta from ENU; beta cancels in
  // what the position method uses: the car's displacement between two detections in the car's own
  // frame at the first, R(-yaw(t0)) (odometry(t1) - odometry(t0)), and its turn yaw(t1) - yaw(t0).
  double ins_yaw_unwrapped = 0.0;
  Eigen::Vector2d odometry = Eigen::Vector2d::Zero();
};

// The car's motion at one GNSS/INS record.
struct CarMotion {
  double time = 0.0;       // [s]
  double speed_mps = 0.0;  // signed, along the car's x axis [m/s]
  double yaw_rate = 0.0;   // positive turning left [rad/s]
};

struct RadarEgoMotionCounts {
  std::int64_t outside_ins_span = 0;  // detections before the first or after the last INS record
  std::int64_t in_ins_gap = 0;        // detections between two INS records too far apart
};

struct RadarEgoMotion {
  std::vector<RadarSample> samples;  // in the detections' order
  std::vector<CarMotion> records;    // one per GNSS/INS record, for segmenting the drive
  RadarEgoMotionCounts counts;
};

// `detections` with times on the INS log's clock (see align_radar_times), `ins` with strictly
// increasing times and at least 2 records. `lever_arm_in_vehicle` is t_V_R's x, y [m] when known.
// Speed and yaw rate are interpolated linearly between the INS records around each detection;
// a detection between two records more than `max_ins_gap_s` apart (a logger pause, a jump in the
// stamps) has no motion to interpolate and is dropped and counted. Nothing here spans a gap, so
// the cost follows the records, not the time. Throws std::invalid_argument when `ins` has fewer
// than 2 records.
RadarEgoMotion radar_ego_motion(std::span<const io::RadarDetection> detections,
                                std::span<const io::InsRecord> ins,
                                const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                                double yaw_rate_window_s = 1.0, double max_ins_gap_s = 1.0);

// Offset [s] to add to radar times to put them on the INS clock: radar_start_unix_time -
// ins_start_unix_time when both logs carry absolute times, 0 otherwise (the generic radar CSV is
// already on the INS clock).
double radar_to_ins_time_offset(double radar_start_unix_time,
                                const std::optional<double>& ins_start_unix_time);

// The radar log's detections with their times on the GNSS/INS log's clock (shifted by
// radar_to_ins_time_offset), as calibrate_radar takes them.
std::vector<io::RadarDetection> detections_on_ins_clock(const io::RadarLog& radar,
                                                        const io::InsLog& ins);

}  // namespace x2car::radar
