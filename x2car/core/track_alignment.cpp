#include "x2car/core/track_alignment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

void check_track(const SensorTrack& track) {
  const std::size_t n = track.time.size();
  if (track.position_enu.size() != n || track.world_from_sensor.size() != n ||
      (!track.velocity_enu.empty() && track.velocity_enu.size() != n)) {
    throw std::invalid_argument(
        "align_track: the track's time, position, attitude and velocity "
        "lists differ in length");
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (!(track.time[i] > track.time[i - 1])) {
      throw std::invalid_argument("align_track: times must strictly increase");
    }
  }
}

// Velocity of the sensor [m/s] from the splines, for tracks without their own: horizontal from
// the sampled planar track, vertical from a spline of z.
std::vector<Eigen::Vector3d> spline_velocities(const SensorTrack& track,
                                               const PlanarTrackSamples& samples,
                                               const TrackAlignmentOptions& options) {
  std::vector<double> z(track.time.size());
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = track.position_enu[i].z();
  const PSpline z_of_time = fit_pspline(track.time, z, options.track.spline);
  std::vector<Eigen::Vector3d> velocities(track.time.size());
  for (std::size_t i = 0; i < velocities.size(); ++i) {
    velocities[i] = {samples.speed[i] * std::cos(samples.heading_enu[i]),
                     samples.speed[i] * std::sin(samples.heading_enu[i]),
                     z_of_time.derivative(track.time[i], 1)};
  }
  return velocities;
}

// Curvature [1/m] from the sensor's yaw rate: d(heading)/dt of a P-spline through the unwrapped
// heading, over the track's speed; 0 where the car stands.
std::vector<double> yaw_rate_curvature(std::span<const double> times,
                                       std::span<const double> headings,
                                       std::span<const double> speeds,
                                       const PSplineOptions& spline_options) {
  std::vector<double> unwrapped(headings.begin(), headings.end());
  for (std::size_t i = 1; i < unwrapped.size(); ++i) {
    unwrapped[i] = unwrapped[i - 1] + angle_difference(headings[i], headings[i - 1]);
  }
  const PSpline heading_of_time = fit_pspline(times, unwrapped, spline_options);
  std::vector<double> curvature(times.size(), 0.0);
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (speeds[i] > 0.0) curvature[i] = heading_of_time.derivative(times[i], 1) / speeds[i];
  }
  return curvature;
}

// Flags samples whose heading offset is more than 90 deg from the mean offset of all moving
// samples: the car was going backwards, so the track's heading is the car's plus pi.
std::vector<std::uint8_t> find_reversing(std::span<const double> offsets,
                                         std::span<const double> speeds, double min_speed) {
  std::vector<double> moving;
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    if (speeds[i] >= min_speed) moving.push_back(offsets[i]);
  }
  std::vector<std::uint8_t> reversing(offsets.size(), 0);
  if (moving.empty() || mean_resultant_length(moving) < 1e-6) return reversing;
  const double usual_offset = circular_mean(moving);
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    reversing[i] =
        speeds[i] >= min_speed && std::abs(angle_difference(offsets[i], usual_offset)) > kPi / 2.0;
  }
  return reversing;
}

// The velocity method's yaw and pitch of one sample (see the header); NaN when the velocity is
// zero or vertical.
void velocity_direction_angles(const Eigen::Vector3d& velocity_enu,
                               const Eigen::Matrix3d& world_from_sensor, double& yaw,
                               double& pitch) {
  yaw = pitch = std::nan("");
  const double speed = velocity_enu.norm();
  if (!(speed > 0.0) || !std::isfinite(speed)) return;
  const Eigen::Vector3d x_vehicle = velocity_enu / speed;
  const Eigen::Vector3d horizontal_left = Eigen::Vector3d::UnitZ().cross(x_vehicle);
  if (!(horizontal_left.norm() > 1e-6)) return;
  const Eigen::Vector3d y_vehicle = horizontal_left.normalized();
  const Eigen::Vector3d z_vehicle = x_vehicle.cross(y_vehicle);
  const Eigen::Vector3d x_sensor = world_from_sensor.col(0);
  yaw = std::atan2(x_sensor.dot(y_vehicle), x_sensor.dot(x_vehicle));
  pitch = -std::asin(std::clamp(x_sensor.dot(z_vehicle), -1.0, 1.0));
}

// Longitudinal acceleration [m/s^2] of the planar track: the projection of (x'', y'') on the
// direction of motion.
std::vector<double> longitudinal_accelerations(const PlanarTrack& track,
                                               const PlanarTrackSamples& samples) {
  std::vector<double> accelerations(samples.time.size(), 0.0);
  for (std::size_t i = 0; i < samples.time.size(); ++i) {
    if (!(samples.speed[i] > 0.0)) continue;
    const double ax = track.x_spline().derivative(samples.time[i], 2);
    const double ay = track.y_spline().derivative(samples.time[i], 2);
    accelerations[i] =
        std::cos(samples.heading_enu[i]) * ax + std::sin(samples.heading_enu[i]) * ay;
  }
  return accelerations;
}

// Least-squares slope of the inlier pitches on the acceleration; 0 when the acceleration hardly
// varies (the slope would be noise).
double fit_pitch_per_acceleration(std::span<const double> pitches,
                                  std::span<const double> accelerations,
                                  const SegmentAverage& first_pass, double min_spread) {
  double sum_a = 0.0, sum_p = 0.0, count = 0.0;
  for (std::size_t i = 0; i < pitches.size(); ++i) {
    if (first_pass.inliers[i] == 0) continue;
    sum_a += accelerations[i];
    sum_p += angle_difference(pitches[i], first_pass.value);
    count += 1.0;
  }
  if (count < 3.0) return 0.0;
  const double mean_a = sum_a / count, mean_p = sum_p / count;
  double covariance = 0.0, variance = 0.0;
  for (std::size_t i = 0; i < pitches.size(); ++i) {
    if (first_pass.inliers[i] == 0) continue;
    const double da = accelerations[i] - mean_a;
    covariance += da * (angle_difference(pitches[i], first_pass.value) - mean_p);
    variance += da * da;
  }
  if (variance / count < min_spread * min_spread) return 0.0;
  return covariance / variance;
}

std::string describe_shortage(const TrackAlignment& alignment,
                              const TrackAlignmentOptions& options) {
  const SegmentationRejections& r = alignment.segmentation.rejections;
  return fmt::format(
      "only {:.1f} s of usable driving (faster than {:g} m/s, |curvature| <= {:g} 1/m, in runs "
      "of at least {:g} s); need {:g} s. Of {} samples: {} too slow, {} in turns, {} reversing, "
      "{} in runs too short, {} trimmed at run ends",
      alignment.valid_duration_s, options.segments.min_speed, options.segments.max_abs_curvature,
      options.segments.min_duration_s, options.min_valid_duration_s, alignment.track.time.size(),
      r.slow, r.curved, r.excluded - alignment.without_direction, r.short_run, r.trimmed);
}

}  // namespace

void TrackAlignmentOptions::Check() const {
  track.Check();
  segments.Check();
  average.Check();
  const OptionsCheck check("TrackAlignmentOptions");
  check.non_negative("min_valid_duration_s", min_valid_duration_s);
  check.positive("min_acceleration_spread", min_acceleration_spread);
  check.non_negative("reversing_test_min_speed", reversing_test_min_speed);
}

TrackAlignment align_track(const SensorTrack& sensor_track, const TrackAlignmentOptions& options) {
  options.Check();
  check_track(sensor_track);
  const std::size_t n = sensor_track.time.size();
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = sensor_track.position_enu[i].x();
    y[i] = sensor_track.position_enu[i].y();
  }
  const PlanarTrack planar = fit_planar_track(sensor_track.time, x, y, options.track);

  TrackAlignment alignment;
  alignment.track = sample_planar_track(planar, sensor_track.time);
  alignment.longitudinal_acceleration = longitudinal_accelerations(planar, alignment.track);
  alignment.velocity_from_sensor = !sensor_track.velocity_enu.empty();
  const std::vector<Eigen::Vector3d> from_splines =
      alignment.velocity_from_sensor ? std::vector<Eigen::Vector3d>{}
                                     : spline_velocities(sensor_track, alignment.track, options);
  const std::span<const Eigen::Vector3d> velocities =
      alignment.velocity_from_sensor ? std::span<const Eigen::Vector3d>(sensor_track.velocity_enu)
                                     : std::span<const Eigen::Vector3d>(from_splines);
  alignment.sensor_heading.resize(n);
  alignment.heading_offset.resize(n);
  alignment.velocity_yaw.resize(n);
  alignment.velocity_pitch.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d& world_from_sensor = sensor_track.world_from_sensor[i];
    alignment.sensor_heading[i] = euler_from_rotation(world_from_sensor).yaw;
    alignment.heading_offset[i] =
        angle_difference(alignment.sensor_heading[i], alignment.track.heading_enu[i]);
    velocity_direction_angles(velocities[i], world_from_sensor, alignment.velocity_yaw[i],
                              alignment.velocity_pitch[i]);
  }
  alignment.reversing = find_reversing(alignment.heading_offset, alignment.track.speed,
                                       options.reversing_test_min_speed);
  // Reversing samples, and the rare moving sample whose velocity gives no direction, are excluded.
  std::vector<std::uint8_t> excluded = alignment.reversing;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(alignment.velocity_yaw[i])) {
      excluded[i] = 1;
      ++alignment.without_direction;
    }
  }
  alignment.gate_curvature =
      options.turn_gate == TurnGate::kSensorYawRate
          ? yaw_rate_curvature(alignment.track.time, alignment.sensor_heading,
                               alignment.track.speed, options.track.spline)
          : alignment.track.curvature;
  alignment.segmentation = segment_runs(alignment.track.time, alignment.track.speed,
                                        alignment.gate_curvature, options.segments, excluded);
  for (const TimeSegment& segment : alignment.segmentation.segments) {
    alignment.valid_duration_s += segment.duration();
  }
  if (alignment.segmentation.segments.empty() ||
      alignment.valid_duration_s < options.min_valid_duration_s) {
    alignment.insufficient_reason = describe_shortage(alignment, options);
    return alignment;
  }
  alignment.yaw = average_over_segments(alignment.track.time, alignment.heading_offset,
                                        alignment.segmentation, options.average);
  alignment.velocity_yaw_estimate = average_over_segments(
      alignment.track.time, alignment.velocity_yaw, alignment.segmentation, options.average);
  alignment.velocity_pitch_estimate = average_over_segments(
      alignment.track.time, alignment.velocity_pitch, alignment.segmentation, options.average);
  if (options.remove_body_pitch) {
    alignment.pitch_per_acceleration = fit_pitch_per_acceleration(
        alignment.velocity_pitch, alignment.longitudinal_acceleration,
        *alignment.velocity_pitch_estimate, options.min_acceleration_spread);
    std::vector<double> corrected = alignment.velocity_pitch;
    for (std::size_t i = 0; i < n; ++i) {
      corrected[i] -= alignment.pitch_per_acceleration * alignment.longitudinal_acceleration[i];
    }
    alignment.velocity_pitch_estimate = average_over_segments(
        alignment.track.time, corrected, alignment.segmentation, options.average);
  }
  return alignment;
}

}  // namespace x2car
