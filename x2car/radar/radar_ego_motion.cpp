#include "x2car/radar/radar_ego_motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/rotation.hpp"

namespace x2car::radar {
namespace {

bool has_device_velocity(std::span<const io::InsRecord> ins) {
  return std::any_of(ins.begin(), ins.end(),
                     [](const io::InsRecord& r) { return r.velocity_enu.head<2>().norm() > 0.0; });
}

// Central differences (one-sided at the ends) of the records i-1, i+1.
std::pair<std::size_t, std::size_t> neighbours(std::size_t i, std::size_t count) {
  return {i == 0 ? 0 : i - 1, std::min(i + 1, count - 1)};
}

// Unwrapped INS yaw [rad], continuous across the +-pi seam.
std::vector<double> unwrapped_yaw(std::span<const io::InsRecord> ins) {
  std::vector<double> yaw(ins.size());
  yaw[0] = ins[0].attitude.yaw;
  for (std::size_t i = 1; i < ins.size(); ++i) {
    yaw[i] = yaw[i - 1] + angle_difference(ins[i].attitude.yaw, ins[i - 1].attitude.yaw);
  }
  return yaw;
}

// Yaw rate at record i: least-squares slope of the unwrapped yaw over the records within
// +-half_window_s (the heading's white noise makes plain differences of 100 Hz records useless).
double yaw_rate_at(std::span<const io::InsRecord> ins, std::span<const double> yaw, std::size_t i,
                   double half_window_s) {
  std::size_t first = i;
  std::size_t last = i;
  while (first > 0 && ins[i].time - ins[first - 1].time <= half_window_s) --first;
  while (last + 1 < ins.size() && ins[last + 1].time - ins[i].time <= half_window_s) ++last;
  if (last == first) {
    first = i == 0 ? 0 : i - 1;
    last = std::min(i + 1, ins.size() - 1);
  }
  double sum_t = 0.0;
  double sum_y = 0.0;
  const auto count = static_cast<double>(last - first + 1);
  for (std::size_t j = first; j <= last; ++j) {
    sum_t += ins[j].time - ins[i].time;
    sum_y += yaw[j] - yaw[i];
  }
  const double mean_t = sum_t / count;
  const double mean_y = sum_y / count;
  double sum_tt = 0.0;
  double sum_ty = 0.0;
  for (std::size_t j = first; j <= last; ++j) {
    const double dt = ins[j].time - ins[i].time - mean_t;
    sum_tt += dt * dt;
    sum_ty += dt * (yaw[j] - yaw[i] - mean_y);
  }
  return sum_tt > 0.0 ? sum_ty / sum_tt : 0.0;
}

// Below this speed a record's course (its velocity's direction) is mostly noise [m/s]: a log
// without velocities differences 2 cm of position noise over 20 ms into 1 m/s.
constexpr double kCourseSpeedMps = 2.0;
// The moving records' courses against the INS heading must gather round one axis this closely
// (mean resultant length of the doubled offsets) to tell the way ahead; else the INS's x axis is.
constexpr double kMinCourseAgreement = 0.5;

// Where the car drives ahead, relative to the INS's x axis [rad]: the INS's mounting yaw, which
// this calibrator does not know and which can be any (a box mounted backwards: 180 deg; sideways:
// +-90). The moving records' offsets of course against heading lie on one axis, ahead and backing
// up at its two ends; most of a drive goes forward (core::majority_axis_end). 0 (the INS's x axis)
// when no record moves or the offsets do not gather round an axis.
double ahead_of_ins(std::span<const io::InsRecord> ins,
                    std::span<const Eigen::Vector3d> velocities) {
  std::vector<double> offsets;
  for (std::size_t i = 0; i < ins.size(); ++i) {
    if (velocities[i].head<2>().norm() < kCourseSpeedMps) continue;
    offsets.push_back(
        angle_difference(std::atan2(velocities[i].y(), velocities[i].x()), ins[i].attitude.yaw));
  }
  return majority_axis_end(offsets, kMinCourseAgreement).value_or(0.0);
}

// Speed from the velocity's norm (3-D: on a grade the car still moves along its x axis, in the
// radar's plane); negative when it points more than 90 deg away from the way ahead (ahead_of_ins:
// the INS's x axis turned by its mounting yaw, whatever that is).
std::vector<CarMotion> car_motion_at_records(std::span<const io::InsRecord> ins,
                                             std::span<const double> yaw,
                                             double yaw_rate_window_s) {
  const bool device_velocity = has_device_velocity(ins);
  std::vector<Eigen::Vector3d> velocities(ins.size());
  for (std::size_t i = 0; i < ins.size(); ++i) {
    const auto [before, after] = neighbours(i, ins.size());
    const double dt = ins[after].time - ins[before].time;
    velocities[i] =
        device_velocity
            ? ins[i].velocity_enu
            : Eigen::Vector3d((ins[after].position_enu - ins[before].position_enu) / dt);
  }
  const double ahead = ahead_of_ins(ins, velocities);
  std::vector<CarMotion> motion(ins.size());
  for (std::size_t i = 0; i < ins.size(); ++i) {
    const Eigen::Vector3d& velocity_enu = velocities[i];
    const double speed = velocity_enu.norm();
    const double course = std::atan2(velocity_enu.y(), velocity_enu.x());
    const bool backwards =
        speed > 0.0 && std::abs(angle_difference(angle_difference(course, ins[i].attitude.yaw),
                                                 ahead)) > kPi / 2.0;
    motion[i].time = ins[i].time;
    motion[i].speed_mps = backwards ? -speed : speed;
    motion[i].yaw_rate = yaw_rate_at(ins, yaw, i, yaw_rate_window_s / 2.0);
  }
  return motion;
}

// The car's path integrated from its speed and the INS yaw (trapezoidal rule), in the frame of the
// INS yaw (radar_ego_motion.hpp): what matters is the path's shape between two detections, which
// the 100 Hz yaw gives without the GNSS position's noise and without knowing the INS mounting.
std::vector<Eigen::Vector2d> dead_reckoning(std::span<const CarMotion> motion,
                                            std::span<const double> yaw) {
  std::vector<Eigen::Vector2d> odometry(motion.size(), Eigen::Vector2d::Zero());
  for (std::size_t i = 1; i < motion.size(); ++i) {
    const Eigen::Vector2d before =
        motion[i - 1].speed_mps * Eigen::Vector2d(std::cos(yaw[i - 1]), std::sin(yaw[i - 1]));
    const Eigen::Vector2d after =
        motion[i].speed_mps * Eigen::Vector2d(std::cos(yaw[i]), std::sin(yaw[i]));
    odometry[i] = odometry[i - 1] + 0.5 * (motion[i].time - motion[i - 1].time) * (before + after);
  }
  return odometry;
}

}  // namespace

RadarEgoMotion radar_ego_motion(std::span<const io::RadarDetection> detections,
                                std::span<const io::InsRecord> ins,
                                const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                                double yaw_rate_window_s, double max_ins_gap_s) {
  if (ins.size() < 2) {
    throw std::invalid_argument("radar_ego_motion: need at least 2 GNSS/INS records");
  }
  const std::vector<double> yaw = unwrapped_yaw(ins);
  RadarEgoMotion result;
  result.records = car_motion_at_records(ins, yaw, yaw_rate_window_s);
  const std::vector<CarMotion>& motion = result.records;
  const std::vector<Eigen::Vector2d> odometry = dead_reckoning(motion, yaw);
  result.samples.reserve(detections.size());
  for (const io::RadarDetection& detection : detections) {
    if (!(detection.time >= ins.front().time && detection.time <= ins.back().time)) {
      ++result.counts.outside_ins_span;
      continue;
    }
    const auto upper = std::upper_bound(
        ins.begin(), ins.end(), detection.time,
        [](double time, const io::InsRecord& record) { return time < record.time; });
    const std::size_t after =
        std::min(static_cast<std::size_t>(upper - ins.begin()), ins.size() - 1);
    const std::size_t before = after - 1;
    if (ins[after].time - ins[before].time > max_ins_gap_s) {
      ++result.counts.in_ins_gap;
      continue;
    }
    const double fraction =
        (detection.time - ins[before].time) / (ins[after].time - ins[before].time);
    RadarSample sample;
    sample.time = detection.time;
    sample.track_id = detection.track_id;
    sample.new_track = detection.new_track;
    sample.range = detection.range;
    sample.azimuth = detection.azimuth;
    sample.range_rate = detection.range_rate;
    sample.car_speed_mps = std::lerp(motion[before].speed_mps, motion[after].speed_mps, fraction);
    sample.yaw_rate = std::lerp(motion[before].yaw_rate, motion[after].yaw_rate, fraction);
    sample.ins_yaw_unwrapped = std::lerp(yaw[before], yaw[after], fraction);
    sample.odometry = odometry[before] + fraction * (odometry[after] - odometry[before]);
    // v_radar = v_car + omega x t_V_R, with v_car = (s, 0) (non-holonomic).
    sample.radar_velocity_in_vehicle = {sample.car_speed_mps, 0.0};
    if (lever_arm_in_vehicle) {
      sample.radar_velocity_in_vehicle +=
          sample.yaw_rate * Eigen::Vector2d(-lever_arm_in_vehicle->y(), lever_arm_in_vehicle->x());
    }
    result.samples.push_back(sample);
  }
  return result;
}

double radar_to_ins_time_offset(double radar_start_unix_time,
                                const std::optional<double>& ins_start_unix_time) {
  if (radar_start_unix_time == 0.0 || !ins_start_unix_time) return 0.0;
  return radar_start_unix_time - *ins_start_unix_time;
}

std::vector<io::RadarDetection> detections_on_ins_clock(const io::RadarLog& radar,
                                                        const io::InsLog& ins) {
  const double offset_s = radar_to_ins_time_offset(radar.start_unix_time, ins.start_unix_time);
  std::vector<io::RadarDetection> detections = radar.detections;
  for (io::RadarDetection& detection : detections) detection.time += offset_s;
  return detections;
}

}  // namespace x2car::radar
