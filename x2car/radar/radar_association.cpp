#include "x2car/radar/radar_association.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "x2car/core/rotation.hpp"

namespace x2car::radar {
namespace {

// One detection of a track in the frame that does not turn with the car (header: q).
struct TrackPoint {
  double time = 0.0;                            // [s]
  Eigen::Vector2d q = Eigen::Vector2d::Zero();  // [m]
};

struct OpenTrack {
  int id = 0;
  std::vector<TrackPoint> recent;  // within the window, oldest first
  double range = 0.0;              // of the last detection [m]
  double range_rate = 0.0;         // [m/s]
  int detections = 0;
};

TrackPoint point_of(const RadarSample& sample) {
  return {sample.time, sample.range * unit_vector(sample.ins_yaw_unwrapped + sample.azimuth)};
}

// Normalised distance (in sigmas) of `sample` from the track's prediction at its time; +inf when
// outside the gate (header, steps 1-2).
double gated_distance(const OpenTrack& track, const RadarSample& sample,
                      const RadarPositionMethodOptions& options) {
  const TrackPoint next = point_of(sample);
  const TrackPoint& last = track.recent.back();
  const double dt = next.time - last.time;
  // Range rate: a target moving straight relative to the radar has d(range rate)/dt = u_perp^2 /
  // range >= 0, u_perp its relative speed across the line of sight, at most the radar's speed
  // plus the target's.
  const double speed = sample.radar_velocity_in_vehicle.norm();
  const double max_cross_speed = speed + options.association_max_target_speed_mps;
  const double range_rate_change = sample.range_rate - track.range_rate;
  const double tolerance = options.association_max_range_rate_jump_mps;
  if (range_rate_change < -tolerance ||
      range_rate_change >
          max_cross_speed * max_cross_speed / std::max(track.range, 1.0) * dt + tolerance) {
    return INFINITY;
  }
  const Eigen::Vector2d along = unit_vector(sample.ins_yaw_unwrapped + sample.azimuth);
  const Eigen::Vector2d across(-along.y(), along.x());
  const double range_var = options.range_sigma_m * options.range_sigma_m;
  const double cross_sigma = sample.range * options.azimuth_sigma;
  const double model_var = options.association_model_sigma_m * options.association_model_sigma_m;
  double along_residual = 0.0;
  double cross_residual = 0.0;
  double along_var = 0.0;
  double cross_var = 0.0;
  if (track.recent.size() == 1) {
    // The target's motion is unknown: along the line of sight the range rate predicts the range;
    // across it a static target moves at +-sqrt(v^2 - range_rate^2) (v the radar's speed), a
    // moving one up to association_max_target_speed_mps beyond that.
    const double range_rate = 0.5 * (track.range_rate + sample.range_rate);
    along_residual = sample.range - track.range - range_rate * dt;
    const double static_cross = std::sqrt(std::max(speed * speed - range_rate * range_rate, 0.0));
    const double cross = (next.q - last.q).dot(across);
    const double nearest =
        std::min(std::abs(cross - static_cross * dt), std::abs(cross + static_cross * dt));
    cross_residual = std::max(0.0, nearest - options.association_max_target_speed_mps * dt);
    along_var = 2.0 * range_var + model_var;
    cross_var = 2.0 * cross_sigma * cross_sigma + model_var;
  } else {
    // The least-squares line q(t) = mean + velocity (t - mean time) through the recent points.
    const double n = static_cast<double>(track.recent.size());
    double mean_time = 0.0;
    Eigen::Vector2d mean_q = Eigen::Vector2d::Zero();
    for (const TrackPoint& p : track.recent) {
      mean_time += p.time / n;
      mean_q += p.q / n;
    }
    double s_tt = 0.0;
    Eigen::Vector2d s_tq = Eigen::Vector2d::Zero();
    for (const TrackPoint& p : track.recent) {
      s_tt += (p.time - mean_time) * (p.time - mean_time);
      s_tq += (p.time - mean_time) * (p.q - mean_q);
    }
    if (!(s_tt > 0.0)) return INFINITY;  // two detections at one time: not a track
    const Eigen::Vector2d velocity = s_tq / s_tt;
    const Eigen::Vector2d innovation = next.q - (mean_q + velocity * (next.time - mean_time));
    along_residual = innovation.dot(along);
    cross_residual = innovation.dot(across);
    const double spread = 1.0 + 1.0 / n + std::pow(next.time - mean_time, 2) / s_tt;
    along_var = range_var * spread + model_var;
    cross_var = cross_sigma * cross_sigma * spread + model_var;
  }
  const double distance_squared =
      along_residual * along_residual / along_var + cross_residual * cross_residual / cross_var;
  const double gate = options.association_gate_sigmas;
  return distance_squared <= gate * gate ? std::sqrt(distance_squared) : INFINITY;
}

void add_point(OpenTrack& track, const RadarSample& sample, double window_s) {
  track.recent.push_back(point_of(sample));
  const double oldest = sample.time - window_s;
  const auto first_kept = std::find_if(track.recent.begin(), track.recent.end(),
                                       [&](const TrackPoint& p) { return p.time >= oldest; });
  // Keep at least the point before the newest, so that the line has two points.
  const auto limit = track.recent.end() - std::min<std::ptrdiff_t>(2, track.recent.size());
  track.recent.erase(track.recent.begin(), std::min(first_kept, limit));
  track.range = sample.range;
  track.range_rate = sample.range_rate;
  ++track.detections;
}

struct Candidate {
  double distance = 0.0;
  std::size_t track = 0;   // into the open tracks
  std::size_t sample = 0;  // into the samples
};

}  // namespace

RadarAssociation associate_detections(std::span<const RadarSample> samples,
                                      const RadarPositionMethodOptions& options) {
  RadarAssociation association;
  association.track_of_sample.assign(samples.size(), -1);
  std::vector<OpenTrack> open;
  const auto close = [&](const OpenTrack& track) {
    if (track.detections >= 2) ++association.tracks_of_two_or_more;
  };
  std::size_t begin = 0;
  while (begin < samples.size()) {
    std::size_t end = begin + 1;
    while (end < samples.size() && samples[end].time == samples[begin].time) ++end;
    const double time = samples[begin].time;
    // Close the tracks that have waited too long.
    std::erase_if(open, [&](const OpenTrack& track) {
      const bool stale = time - track.recent.back().time > options.max_track_gap_s;
      if (stale) close(track);
      return stale;
    });
    // Gate and assign (steps 1-3).
    std::vector<Candidate> candidates;
    for (std::size_t k = 0; k < open.size(); ++k) {
      for (std::size_t i = begin; i < end; ++i) {
        const double distance = gated_distance(open[k], samples[i], options);
        if (std::isfinite(distance)) candidates.push_back({distance, k, i});
      }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.distance != b.distance
                 ? a.distance < b.distance
                 : (a.track != b.track ? a.track < b.track : a.sample < b.sample);
    });
    std::vector<std::uint8_t> track_taken(open.size(), 0);
    for (const Candidate& c : candidates) {
      if (track_taken[c.track] || association.track_of_sample[c.sample] >= 0) continue;
      track_taken[c.track] = 1;
      association.track_of_sample[c.sample] = open[c.track].id;
      add_point(open[c.track], samples[c.sample], options.association_window_s);
    }
    for (std::size_t i = begin; i < end; ++i) {
      if (association.track_of_sample[i] >= 0) continue;
      OpenTrack track;
      track.id = static_cast<int>(association.tracks++);
      add_point(track, samples[i], options.association_window_s);
      association.track_of_sample[i] = track.id;
      open.push_back(std::move(track));
    }
    begin = end;
  }
  for (const OpenTrack& track : open) close(track);
  return association;
}

}  // namespace x2car::radar
