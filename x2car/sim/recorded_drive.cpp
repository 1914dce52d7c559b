#include "x2car/sim/recorded_drive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::sim {
namespace {

constexpr double kDamping = 0.7;   // of the path-following controller (header)
constexpr int kSubsteps = 8;       // Simpson steps per knot interval when integrating the fit
constexpr double kMinPathM = 1.0;  // shortest path that makes a route [m]
constexpr double kMaxPathM = 1e6;  // longest, that of a generated route's plan [m]

// The recorded path's horizontal track as a polyline of distinct points with their distance
// along it.
struct Track {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> distance;  // [m]

  // The point and chord heading at distance d (clamped to the track).
  Eigen::Vector2d point_at(double d) const {
    const std::size_t i = segment_at(d);
    const double f = std::clamp((d - distance[i]) / (distance[i + 1] - distance[i]), 0.0, 1.0);
    return points[i] + f * (points[i + 1] - points[i]);
  }
  double heading_at(double d) const {
    const std::size_t i = segment_at(d);
    const Eigen::Vector2d chord = points[i + 1] - points[i];
    return std::atan2(chord.y(), chord.x());
  }
  std::size_t segment_at(double d) const {
    const auto after = std::upper_bound(distance.begin(), distance.end(), d);
    const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(after - distance.begin(), 1));
    return std::min(i, distance.size() - 1) - 1;
  }
  double length() const { return distance.back(); }
};

// The path's curvature at d: heading change over +-half the smoothing length, per metre.
double track_curvature(const Track& track, double d, double smoothing) {
  const double a = std::max(0.0, d - 0.5 * smoothing);
  const double b = std::min(track.length(), d + 0.5 * smoothing);
  if (b - a < 1e-6) return 0.0;
  return angle_difference(track.heading_at(b), track.heading_at(a)) / (b - a);
}

// Plan-view state of the fit while it is integrated.
struct PlanState {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double heading = 0.0;  // unwrapped [rad]
};

// Advances the state by `step` [m] with curvature linear from k0 to k1 (Simpson's rule, as exact
// as Route's own integration to far below a millimetre).
PlanState advance(PlanState state, double k0, double k1, double step) {
  const double h = step / kSubsteps;
  const auto heading_at = [&](double sigma) {
    return state.heading + k0 * sigma + 0.5 * (k1 - k0) * sigma * sigma / step;
  };
  Eigen::Vector2d position = state.position;
  for (int j = 0; j < kSubsteps; ++j) {
    const double s0 = j * h, s1 = s0 + 0.5 * h, s2 = s0 + h;
    const auto direction = [&](double sigma) {
      return Eigen::Vector2d(std::cos(heading_at(sigma)), std::sin(heading_at(sigma)));
    };
    position += h / 6.0 * (direction(s0) + 4.0 * direction(s1) + direction(s2));
  }
  return {position, heading_at(step)};
}

// The curvature that steers from `state` (at distance d along the fit) back onto the track.
double steer(const Track& track, const PlanState& state, double d,
             const RecordedDriveOptions& options) {
  // The nearest track point within a few metres of d (the fit's length tracks the path's).
  double best_d = d;
  double best = std::numeric_limits<double>::infinity();
  for (double probe = d - 3.0; probe <= d + 3.0; probe += 0.05) {
    const double q = std::clamp(probe, 0.0, track.length());
    const double distance = (track.point_at(q) - state.position).squaredNorm();
    if (distance < best) best = distance, best_d = q;
  }
  const double heading = track.heading_at(best_d);
  const Eigen::Vector2d left(-std::sin(heading), std::cos(heading));
  const double e = left.dot(state.position - track.point_at(best_d));
  const double de = angle_difference(state.heading, heading);
  const double L = options.preview_m;
  const double kappa = track_curvature(track, best_d, L) - e / (L * L) - 2.0 * kDamping * de / L;
  return std::clamp(kappa, -options.max_curvature, options.max_curvature);
}

}  // namespace

void RecordedDriveOptions::Check() const {
  const OptionsCheck check("RecordedDriveOptions");
  // One knot (and ~120 track probes) every knot_spacing_m of the path: below 0.1 m it only stalls.
  check.in_range("knot_spacing_m", knot_spacing_m, 0.1, 100.0);
  check.positive("preview_m", preview_m);
  check.non_negative("min_step_m", min_step_m);
  check.positive("max_curvature", max_curvature);
  check.non_negative("min_duration_s", min_duration_s);
}

RecordedDrive fit_recorded_drive(std::span<const StampedPose> poses,
                                 const RecordedDriveOptions& options) {
  options.Check();
  if (poses.size() < 2) reject_argument("recorded drive: needs at least 2 poses");
  for (std::size_t i = 1; i < poses.size(); ++i) {
    if (!(poses[i].time > poses[i - 1].time)) {
      reject_argument("recorded drive: pose times must strictly increase (pose {})", i);
    }
  }
  if (!(poses.back().time - poses.front().time >= options.min_duration_s)) {
    reject_argument("recorded drive: the recording is shorter than min_duration_s ({:g} s)",
                    options.min_duration_s);
  }
  const Eigen::Vector3d origin = poses.front().world_from_body.translation();

  // Each pose's distance along the track; standing poses keep the last distance.
  Track track;
  std::vector<double> times, arc_lengths;
  for (const StampedPose& pose : poses) {
    const Eigen::Vector2d p = (pose.world_from_body.translation() - origin).head<2>();
    if (track.points.empty()) {
      track.points.push_back(p);
      track.distance.push_back(0.0);
    } else if ((p - track.points.back()).norm() >= std::max(options.min_step_m, 1e-9)) {
      track.distance.push_back(track.distance.back() + (p - track.points.back()).norm());
      track.points.push_back(p);
    }
    times.push_back(pose.time - poses.front().time);
    arc_lengths.push_back(track.distance.back());
  }
  if (!(track.points.size() >= 2 && track.length() >= kMinPathM)) {
    reject_argument("recorded drive: the path must be at least 1 m long");
  }
  // As long as a generated route may be: a longer path (a wild jump between poses) would take
  // minutes of fitting only to fail on the route's table.
  if (!(track.length() <= kMaxPathM)) {
    reject_argument("recorded drive: the path must be at most 1000 km long");
  }

  // Knots every knot_spacing_m, the last one at the track's end.
  RoadPlan plan;
  plan.initial_heading_enu = track.heading_at(0.0);
  PlanState state{Eigen::Vector2d::Zero(), plan.initial_heading_enu};
  const auto knots =
      static_cast<std::size_t>(std::ceil(track.length() / options.knot_spacing_m - 1e-9));
  double kappa = track_curvature(track, 0.0, options.preview_m);
  plan.curvature.push_back({0.0, kappa});
  for (std::size_t k = 1; k <= knots; ++k) {
    const double s0 = plan.curvature.back().s;
    const double s1 = std::min(track.length(), static_cast<double>(k) * options.knot_spacing_m);
    // Steer from the state a knot ahead if the curvature held: the command takes effect over the
    // interval, not after it.
    const PlanState ahead = advance(state, kappa, kappa, s1 - s0);
    const double next = steer(track, ahead, s1, options);
    state = advance(state, kappa, next, s1 - s0);
    plan.curvature.push_back({s1, next});
    kappa = next;
  }
  const double length = track.length();
  for (double& s : arc_lengths) s = std::min(s, length);
  return {Route(std::move(plan), VerticalProfile{}), std::move(times), std::move(arc_lengths),
          origin};
}

std::vector<StampedPose> kitti_poses_to_z_up(std::span<const StampedPose> poses) {
  Eigen::Matrix3d z_up_from_camera;
  z_up_from_camera << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d world_from_kitti = Eigen::Isometry3d::Identity();
  world_from_kitti.linear() = z_up_from_camera;
  std::vector<StampedPose> converted;
  converted.reserve(poses.size());
  for (const StampedPose& pose : poses) {
    converted.push_back({pose.time, world_from_kitti * pose.world_from_body});
  }
  return converted;
}

}  // namespace x2car::sim
