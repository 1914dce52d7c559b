#include "x2car/core/track_alignment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/track_heading.hpp"

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

// Samples [begin, end) between two time gaps.
struct Piece {
  std::size_t begin = 0;
  std::size_t end = 0;
};

std::vector<Piece> split_at_gaps(std::span<const double> times, double split_gap_s) {
  std::vector<Piece> pieces;
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= times.size(); ++i) {
    if (i == times.size() || times[i] - times[i - 1] > split_gap_s) {
      pieces.push_back({begin, i});
      begin = i;
    }
  }
  return pieces;
}

// A piece is smoothed when it could hold a run and has the samples the splines need.
bool smoothable(std::span<const double> times, const Piece& piece,
                const TrackAlignmentOptions& options) {
  const auto needed = static_cast<std::size_t>(options.track.spline.degree + 2);
  return piece.end - piece.begin >= needed &&
         times[piece.end - 1] - times[piece.begin] >= options.segments.min_duration_s;
}

// What the splines of one piece give at its samples.
struct PieceKinematics {
  PlanarTrackSamples track;
  std::vector<double> longitudinal_acceleration;  // [m/s^2]
  std::vector<Eigen::Vector3d> spline_velocity;   // [m/s]; empty when the sensor has its own
};

// Velocity of the sensor [m/s] from the splines, for tracks without their own: horizontal from
// the sampled planar track, vertical from a spline of z.
std::vector<Eigen::Vector3d> spline_velocities(std::span<const double> times,
                                               std::span<const Eigen::Vector3d> positions,
                                               const PlanarTrackSamples& samples,
                                               const TrackAlignmentOptions& options) {
  std::vector<double> z(times.size());
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = positions[i].z();
  const PSpline z_of_time = fit_pspline(times, z, options.track.spline);
  std::vector<Eigen::Vector3d> velocities(times.size());
  for (std::size_t i = 0; i < velocities.size(); ++i) {
    velocities[i] = {samples.speed[i] * std::cos(samples.heading_enu[i]),
                     samples.speed[i] * std::sin(samples.heading_enu[i]),
                     z_of_time.derivative(times[i], 1)};
  }
  return velocities;
}

// The velocity method's yaw and pitch of one sample (see the header); NaN when the velocity is
// zero or vertical.
void velocity_direction_angles(const Eigen::Vector3d& velocity_enu,
                               const Eigen::Matrix3d& world_from_sensor, double& yaw, double& pitch,
                               double& elevation) {
  yaw = pitch = elevation = std::nan("");
  const double speed = velocity_enu.norm();
  if (!(speed > 0.0) || !std::isfinite(speed)) return;
  const Eigen::Vector3d x_vehicle = velocity_enu / speed;
  elevation = std::asin(std::clamp(x_vehicle.dot(world_from_sensor.col(2)), -1.0, 1.0));
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

PieceKinematics smooth_piece(const SensorTrack& sensor_track, const Piece& piece,
                             const TrackAlignmentOptions& options) {
  const std::size_t n = piece.end - piece.begin;
  const std::span<const double> times(sensor_track.time.data() + piece.begin, n);
  const std::span<const Eigen::Vector3d> positions(sensor_track.position_enu.data() + piece.begin,
                                                   n);
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = positions[i].x();
    y[i] = positions[i].y();
  }
  const PlanarTrack planar = fit_planar_track(times, x, y, options.track);
  PieceKinematics kinematics;
  kinematics.track = sample_planar_track(planar, times);
  kinematics.longitudinal_acceleration = longitudinal_accelerations(planar, kinematics.track);
  if (sensor_track.velocity_enu.empty()) {
    kinematics.spline_velocity = spline_velocities(times, positions, kinematics.track, options);
  }
  return kinematics;
}

template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

// The samples of a piece too short to smooth: no speed, no direction.
void append_unsmoothed(std::span<const double> times, const Piece& piece, TrackAlignment& alignment,
                       std::vector<Eigen::Vector3d>& velocities) {
  const double nan = std::nan("");
  PlanarTrackSamples& track = alignment.track;
  for (std::size_t i = piece.begin; i < piece.end; ++i) {
    track.time.push_back(times[i]);
    track.x.push_back(nan);
    track.y.push_back(nan);
    track.speed.push_back(0.0);
    track.heading_enu.push_back(nan);
    track.curvature.push_back(nan);
    alignment.longitudinal_acceleration.push_back(0.0);
    velocities.push_back(Eigen::Vector3d::Constant(nan));
  }
}

// Smooths each piece between time gaps on its own and lays the results end to end, one entry per
// input sample. Returns the velocities the velocity method uses (the sensor's or the splines').
std::vector<Eigen::Vector3d> smooth_pieces(const SensorTrack& sensor_track,
                                           const TrackAlignmentOptions& options,
                                           TrackAlignment& alignment,
                                           std::vector<std::uint8_t>& in_short_piece) {
  std::vector<Eigen::Vector3d> velocities;
  in_short_piece.assign(sensor_track.time.size(), 0);
  for (const Piece& piece : split_at_gaps(sensor_track.time, options.split_gap_s)) {
    if (!smoothable(sensor_track.time, piece, options)) {
      ++alignment.short_pieces;
      alignment.in_short_pieces += static_cast<std::int64_t>(piece.end - piece.begin);
      std::fill(in_short_piece.begin() + piece.begin, in_short_piece.begin() + piece.end, 1);
      append_unsmoothed(sensor_track.time, piece, alignment, velocities);
      continue;
    }
    ++alignment.pieces;
    const PieceKinematics kinematics = smooth_piece(sensor_track, piece, options);
    PlanarTrackSamples& track = alignment.track;
    append(track.time, kinematics.track.time);
    append(track.x, kinematics.track.x);
    append(track.y, kinematics.track.y);
    append(track.speed, kinematics.track.speed);
    append(track.heading_enu, kinematics.track.heading_enu);
    append(track.curvature, kinematics.track.curvature);
    append(alignment.longitudinal_acceleration, kinematics.longitudinal_acceleration);
    if (kinematics.spline_velocity.empty()) {
      velocities.insert(velocities.end(), sensor_track.velocity_enu.begin() + piece.begin,
                        sensor_track.velocity_enu.begin() + piece.end);
    } else {
      append(velocities, kinematics.spline_velocity);
    }
  }
  return velocities;
}

// The sensor's yaw rate over its speed [1/m], per piece (the yaw-rate spline must not span a gap
// either); NaN in the short pieces.
std::vector<double> yaw_rate_curvatures(const TrackAlignment& alignment,
                                        std::span<const std::uint8_t> in_short_piece,
                                        const TrackAlignmentOptions& options) {
  std::vector<double> curvature(alignment.track.time.size(), std::nan(""));
  for (const Piece& piece : split_at_gaps(alignment.track.time, options.split_gap_s)) {
    if (in_short_piece[piece.begin]) continue;
    const std::size_t n = piece.end - piece.begin;
    const std::vector<double> piece_curvature = yaw_rate_curvature(
        std::span<const double>(alignment.track.time).subspan(piece.begin, n),
        std::span<const double>(alignment.sensor_heading).subspan(piece.begin, n),
        std::span<const double>(alignment.track.speed).subspan(piece.begin, n),
        options.track.spline);
    std::copy(piece_curvature.begin(), piece_curvature.end(), curvature.begin() + piece.begin);
  }
  return curvature;
}

// The gates with turns used: the lateral acceleration instead of the paper's curvature limit.
SegmentationOptions turn_segmentation(const TrackAlignmentOptions& options) {
  SegmentationOptions segments = options.segments;
  segments.max_abs_curvature = options.turns.max_abs_curvature;
  segments.max_abs_lateral_acceleration = options.turns.max_lateral_acceleration;
  segments.end_trim_s = options.turns.end_trim_s;
  segments.min_duration_s = options.turns.min_run_s;
  return segments;
}

double total_duration(const Segmentation& segmentation) {
  double duration = 0.0;
  for (const TimeSegment& segment : segmentation.segments) duration += segment.duration();
  return duration;
}

// Why a fitted lever arm cannot be used, or nothing.
std::optional<std::string> lever_arm_rejection(const LeverArmFit& fit, const TurnOptions& turns) {
  if (!std::isfinite(fit.lever_arm_x_std) || fit.curvature_spread < turns.min_curvature_spread) {
    return fmt::format(
        "the curvature varies too little over the valid samples to fit the lever arm (standard "
        "deviation {:.4f} 1/m, need {:g})",
        fit.curvature_spread, turns.min_curvature_spread);
  }
  if (std::abs(fit.lever_arm_x) > turns.max_abs_lever_arm_x) {
    return fmt::format("the fitted lever arm x = {:.2f} m is beyond +-{:g} m", fit.lever_arm_x,
                       turns.max_abs_lever_arm_x);
  }
  const double yaw_std = std::abs(fit.mean_curvature) * fit.lever_arm_x_std;
  if (yaw_std > turns.max_lever_arm_yaw_std) {
    return fmt::format(
        "the lever arm (x = {:.2f} +- {:.2f} m) leaves {:.3f} deg of uncertainty in the yaw "
        "(more than {:g} deg): the turns go mostly one way",
        fit.lever_arm_x, fit.lever_arm_x_std, deg_from_rad(yaw_std),
        deg_from_rad(turns.max_lever_arm_yaw_std));
  }
  return std::nullopt;
}

// Chooses the valid samples and the lever arm (see the header): with turns used, the gates on
// lateral acceleration and the given or fitted lever arm; else, or when the fitted one cannot be
// used, the paper's gates. Adds the lever arm's shift to both per-sample yaws.
void segment_and_correct(const TrackAlignmentOptions& options,
                         std::span<const std::uint8_t> excluded, TrackAlignment& alignment) {
  const TurnOptions& turns = options.turns;
  const auto segment_with = [&](const SegmentationOptions& segments) {
    return segment_runs(alignment.track.time, alignment.track.speed, alignment.gate_curvature,
                        segments, excluded);
  };
  alignment.turns_used = turns.samples == TurnSamples::kUse;
  alignment.lever_arm_x = turns.lever_arm ? turns.lever_arm->x() : 0.0;
  alignment.segmentation =
      segment_with(alignment.turns_used ? turn_segmentation(options) : options.segments);
  if (alignment.turns_used && !turns.lever_arm &&
      total_duration(alignment.segmentation) >= options.min_valid_duration_s) {
    // The device's velocity is the cleanest measure of the sensor's lateral velocity; without it
    // the track's heading carries the same information.
    const std::vector<double>& offsets =
        alignment.velocity_from_sensor ? alignment.velocity_yaw : alignment.heading_offset;
    alignment.lever_arm_fit =
        fit_lever_arm_x(offsets, alignment.yaw_rate_curvature, alignment.segmentation, turns.fit);
    alignment.lever_arm_rejected = lever_arm_rejection(*alignment.lever_arm_fit, turns);
    if (alignment.lever_arm_rejected) {
      alignment.turns_used = false;
      alignment.segmentation = segment_with(options.segments);
    } else {
      alignment.lever_arm_x = alignment.lever_arm_fit->lever_arm_x;
    }
  }
  alignment.lever_arm_shift =
      lever_arm_heading_shift(alignment.yaw_rate_curvature, alignment.lever_arm_x);
  for (std::size_t i = 0; i < alignment.lever_arm_shift.size(); ++i) {
    const double shift = alignment.lever_arm_shift[i];
    if (!std::isfinite(shift)) continue;  // short pieces: never in a segment
    alignment.heading_offset[i] = wrap_angle(alignment.heading_offset[i] + shift);
    alignment.velocity_yaw[i] = wrap_angle(alignment.velocity_yaw[i] + shift);
  }
}

// The fitted lever arm's uncertainty passes into the yaw through the mean curvature of the samples.
void add_lever_arm_uncertainty(const TrackAlignment& alignment, SegmentAverage& yaw) {
  if (!alignment.turns_used || !alignment.lever_arm_fit) return;
  const LeverArmFit& fit = *alignment.lever_arm_fit;
  yaw.standard_error = std::hypot(yaw.standard_error, fit.mean_curvature * fit.lever_arm_x_std);
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

// The mean of a per-sample angle over the segments; with remove_body_pitch its slope on the
// longitudinal acceleration (`slope`, 0 when not fitted) is fitted and taken out first.
SegmentAverage average_without_body_pitch(const TrackAlignment& alignment,
                                          std::span<const double> angles,
                                          const TrackAlignmentOptions& options, double& slope) {
  const SegmentAverage plain =
      average_over_segments(alignment.track.time, angles, alignment.segmentation, options.average);
  slope = 0.0;
  if (!options.remove_body_pitch) return plain;
  slope = fit_pitch_per_acceleration(angles, alignment.longitudinal_acceleration, plain,
                                     options.min_acceleration_spread);
  std::vector<double> corrected(angles.begin(), angles.end());
  for (std::size_t i = 0; i < corrected.size(); ++i) {
    corrected[i] -= slope * alignment.longitudinal_acceleration[i];
  }
  return average_over_segments(alignment.track.time, corrected, alignment.segmentation,
                               options.average);
}

std::string describe_shortage(const TrackAlignment& alignment,
                              const TrackAlignmentOptions& options) {
  const SegmentationRejections& r = alignment.segmentation.rejections;
  const std::string turn_gate =
      alignment.turns_used
          ? fmt::format("lateral acceleration <= {:g} m/s^2",
                        options.turns.max_lateral_acceleration)
          : fmt::format("|curvature| <= {:g} 1/m", options.segments.max_abs_curvature);
  return fmt::format(
      "only {:.1f} s of usable driving (faster than {:g} m/s, {}, in runs of at least {:g} s); "
      "need {:g} s. Of {} samples: {} too slow, {} in turns, {} reversing, {} in runs too short, "
      "{} trimmed at run ends, {} in {} pieces between time gaps too short to smooth{}",
      alignment.valid_duration_s, options.segments.min_speed, turn_gate,
      alignment.turns_used ? options.turns.min_run_s : options.segments.min_duration_s,
      options.min_valid_duration_s, alignment.track.time.size(), r.slow, r.curved,
      alignment.reversing_samples, r.short_run, r.trimmed, alignment.in_short_pieces,
      alignment.short_pieces,
      alignment.lever_arm_rejected ? "; turns not used: " + *alignment.lever_arm_rejected
                                   : std::string());
}

constexpr std::array<EnumName<TurnSamples>, 2> kTurnSamplesNames{{
    {TurnSamples::kUse, "use"},
    {TurnSamples::kExclude, "exclude"},
}};

}  // namespace

std::string to_string(TurnSamples turns) { return enum_to_string(kTurnSamplesNames, turns); }

TurnSamples turn_samples_from_string(std::string_view name) {
  return enum_from_string(kTurnSamplesNames, name, "turn samples");
}

std::vector<std::string> turn_samples_names() { return enum_names(kTurnSamplesNames); }

void TurnOptions::Check() const {
  fit.Check();
  const OptionsCheck check("TurnOptions");
  check.positive("max_lateral_acceleration", max_lateral_acceleration);
  check.positive("max_abs_curvature", max_abs_curvature);
  check.non_negative("end_trim_s", end_trim_s);
  check.non_negative("min_run_s", min_run_s);
  check.that(!lever_arm || lever_arm->allFinite(), "lever_arm", "must be finite");
  check.non_negative("min_curvature_spread", min_curvature_spread);
  check.positive("max_abs_lever_arm_x", max_abs_lever_arm_x);
  check.positive("max_lever_arm_yaw_std", max_lever_arm_yaw_std);
}

void TrackAlignmentOptions::Check() const {
  track.Check();
  segments.Check();
  turns.Check();
  average.Check();
  const OptionsCheck check("TrackAlignmentOptions");
  check.non_negative("min_valid_duration_s", min_valid_duration_s);
  check.positive("min_acceleration_spread", min_acceleration_spread);
  check.non_negative("reversing_test_min_speed", reversing_test_min_speed);
  check.positive("split_gap_s", split_gap_s);
}

TrackAlignment align_track(const SensorTrack& sensor_track, const TrackAlignmentOptions& options) {
  options.Check();
  check_track(sensor_track);
  const std::size_t n = sensor_track.time.size();
  TrackAlignment alignment;
  alignment.velocity_from_sensor = !sensor_track.velocity_enu.empty();
  std::vector<std::uint8_t> in_short_piece;
  const std::vector<Eigen::Vector3d> velocities =
      smooth_pieces(sensor_track, options, alignment, in_short_piece);
  alignment.sensor_heading = sensor_headings(sensor_track.world_from_sensor);
  alignment.heading_offset = heading_offsets(alignment.sensor_heading, alignment.track.heading_enu);
  alignment.velocity_yaw.resize(n);
  alignment.velocity_pitch.resize(n);
  alignment.velocity_elevation.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    velocity_direction_angles(velocities[i], sensor_track.world_from_sensor[i],
                              alignment.velocity_yaw[i], alignment.velocity_pitch[i],
                              alignment.velocity_elevation[i]);
  }
  alignment.reversing = find_reversing(alignment.heading_offset, alignment.track.speed,
                                       options.reversing_test_min_speed);
  alignment.reversing_samples = std::ranges::count(alignment.reversing, 1);
  // Samples in short pieces, reversing samples, and the rare moving sample whose velocity gives no
  // direction are excluded, each counted once.
  std::vector<std::uint8_t> excluded = alignment.reversing;
  for (std::size_t i = 0; i < n; ++i) {
    if (in_short_piece[i]) {
      excluded[i] = 1;
    } else if (!excluded[i] && !std::isfinite(alignment.velocity_yaw[i])) {
      excluded[i] = 1;
      ++alignment.without_direction;
    }
  }
  alignment.yaw_rate_curvature = yaw_rate_curvatures(alignment, in_short_piece, options);
  alignment.gate_curvature = options.turn_gate == TurnGate::kTrackCurvature
                                 ? alignment.track.curvature
                                 : alignment.yaw_rate_curvature;
  segment_and_correct(options, excluded, alignment);
  for (const TimeSegment& segment : alignment.segmentation.segments) {
    alignment.valid_duration_s += segment.duration();
  }
  if (alignment.segmentation.segments.empty() ||
      alignment.valid_duration_s < options.min_valid_duration_s) {
    alignment.insufficient_reason = describe_shortage(alignment, options);
    return alignment;
  }
  alignment.yaw = track_heading_yaw(alignment.track.time, alignment.heading_offset,
                                    alignment.segmentation, options.average);
  alignment.velocity_yaw_estimate = average_over_segments(
      alignment.track.time, alignment.velocity_yaw, alignment.segmentation, options.average);
  add_lever_arm_uncertainty(alignment, *alignment.yaw);
  add_lever_arm_uncertainty(alignment, *alignment.velocity_yaw_estimate);
  alignment.velocity_pitch_estimate = average_without_body_pitch(
      alignment, alignment.velocity_pitch, options, alignment.pitch_per_acceleration);
  double elevation_per_acceleration = 0.0;
  alignment.velocity_elevation_estimate = average_without_body_pitch(
      alignment, alignment.velocity_elevation, options, elevation_per_acceleration);
  return alignment;
}

}  // namespace x2car
