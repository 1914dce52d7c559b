#include "x2car/sim/vehicle_motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "x2car/core/options_check.hpp"

namespace x2car::sim {
namespace {

// Random streams (Random::derive_seed; route.cpp uses 1 and 2), one per kind of draw, so that the
// cruise targets do not change when a stop is added.
constexpr std::uint64_t kTargetStream = 3;
constexpr std::uint64_t kStopStream = 4;
constexpr double kMaxFilterStep = 0.005;   // suspension integration step, << 1 / (2 pi 1.5 Hz) [s]
constexpr double kMaxSamples = 1e7;        // guards memory (~3 GB of states) [samples]
constexpr double kRouteMargin = 100.0;     // extra route length in route_length_for [m]
constexpr double kStraightMinSpeed = 1.0;  // [m/s], as VehicleState::straight says
constexpr double kStraightMaxCurvature = 1e-4;  // [1/m]
constexpr double kNodeMerge = 1e-6;             // profile nodes closer than this are one [m]
constexpr int kReverseFitTries = 5;             // attempts to fit the final reversal into the log

// Speed at distances u from where a drive starts (u[0] = 0) [m]: v >= 0 [m/s] with constant
// acceleration between nodes (v^2 linear in u), and the time to stand on arrival at a node [s].
struct SpeedProfile {
  std::vector<double> u, v, stand_s;
};

// Constant acceleration along the route, or standing (v0 = a = 0):
//   s(tau) = s0 + direction * (v0 tau + a tau^2 / 2),   0 <= tau <= duration.
struct MotionCell {
  double t0 = 0.0, duration = 0.0, s0 = 0.0, v0 = 0.0, a = 0.0, direction = 1.0;
};

// Position, signed ds/dt and d2s/dt2 along the route (s is the horizontal arc length).
struct Kinematics {
  double s = 0.0, s_dot = 0.0, s_ddot = 0.0;
};

// The car's motion as consecutive cells in time.
class Timeline {
 public:
  explicit Timeline(double s) : s_(s) {}

  double end_time() const { return t_; }

  void stand(double duration) {
    if (duration > 0.0) push({t_, duration, s_, 0.0, 0.0, 1.0});
  }

  // Drives the profile from the current position, forwards (+1) or backwards (-1) along s.
  void drive(const SpeedProfile& profile, double direction) {
    const double start = s_;
    for (std::size_t i = 0; i + 1 < profile.u.size(); ++i) {
      const double du = profile.u[i + 1] - profile.u[i];
      const double v0 = profile.v[i], v1 = profile.v[i + 1];
      if (v0 + v1 > 0.0) {  // constant acceleration: time = distance / mean speed
        push({t_, 2.0 * du / (v0 + v1), s_, v0, (v1 * v1 - v0 * v0) / (2.0 * du), direction});
      }
      s_ = start + direction * profile.u[i + 1];
      stand(profile.stand_s[i + 1]);
    }
  }

  // Covers `distance` [m] forwards in `duration` [s] (> 0) at constant speed.
  void cruise(double distance, double duration) {
    push({t_, duration, s_, distance / duration, 0.0, 1.0});
    s_ += distance;
  }

  Kinematics at(double t) const {
    const auto after =
        std::upper_bound(cells_.begin(), cells_.end(), t,
                         [](double value, const MotionCell& c) { return value < c.t0; });
    if (after == cells_.begin()) return {s_, 0.0, 0.0};  // an empty timeline stands
    const MotionCell& cell = *(after - 1);
    const double tau = std::clamp(t - cell.t0, 0.0, cell.duration);
    const double distance = cell.v0 * tau + 0.5 * cell.a * tau * tau;
    return {cell.s0 + cell.direction * distance, cell.direction * (cell.v0 + cell.a * tau),
            cell.direction * cell.a};
  }

 private:
  void push(const MotionCell& cell) {
    cells_.push_back(cell);
    t_ += cell.duration;
  }

  std::vector<MotionCell> cells_;
  double t_ = 0.0;  // end of the last cell [s]
  double s_;        // where the car is at t_ [m]
};

// ---- speed profile --------------------------------------------------------------------------

// Nodes every profile_step_m on [0, s_end], plus the stop points in between and s_end.
std::vector<double> profile_nodes(const Route& route, double s_end, double step) {
  std::vector<double> nodes;
  const auto count = static_cast<std::size_t>(std::floor(s_end / step));
  for (std::size_t i = 0; i <= count; ++i) nodes.push_back(static_cast<double>(i) * step);
  for (double stop : route.stop_points()) {
    if (stop < s_end) nodes.push_back(stop);
  }
  nodes.push_back(s_end);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end(),
                          [](double a, double b) { return b - a < kNodeMerge; }),
              nodes.end());
  nodes.back() = s_end;
  return nodes;
}

// Road kind at s: the route's section there, or `fallback` on a route without sections.
// `section` is a cursor for increasing s.
Scenario road_kind_at(const Route& route, double s, Scenario fallback, std::size_t& section) {
  const auto& sections = route.sections();
  if (sections.empty()) return fallback;
  while (section + 1 < sections.size() && s >= sections[section].s_end) ++section;
  return sections[section].road_kind;
}

// Speed caps at the nodes [m/s along s]: the cruise target of the stretch (a new one is drawn
// per stretch of the road kind's length), and the speed at which the sharpest curvature on the
// neighbouring cells reaches the lateral-acceleration limit. Between nodes v^2 is linear and
// |kappa| <= that maximum, so v^2 |kappa| stays below the limit everywhere, not only at nodes.
std::vector<double> speed_caps(const Route& route, const std::vector<double>& nodes,
                               Scenario fallback, const VehicleMotionOptions& options,
                               Random& rng) {
  // lateral = s_dot^2 kappa sqrt(1 + grade^2) (see the header); bound the grade once.
  const double grade_factor = std::sqrt(1.0 + std::pow(route.max_abs_grade(), 2));
  std::vector<double> caps(nodes.size());
  std::size_t section = 0;
  double stretch_end = -1.0, target = 0.0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const DrivingStyle& style =
        driving_style(options, road_kind_at(route, nodes[i], fallback, section));
    if (nodes[i] >= stretch_end) {
      const double section_end =
          route.sections().empty() ? route.length() : route.sections()[section].s_end;
      stretch_end =
          std::min(nodes[i] + rng.uniform(style.min_stretch_m, style.max_stretch_m), section_end);
      target = rng.uniform(style.min_speed_mps, style.max_speed_mps);
    }
    const double grade = route.grade_at(nodes[i]);
    caps[i] = target / std::sqrt(1.0 + grade * grade);  // the 3-D speed is the target
    const double curvature = route.max_abs_curvature(nodes[i == 0 ? 0 : i - 1],
                                                     nodes[std::min(i + 1, nodes.size() - 1)]);
    if (curvature > 0.0) {
      caps[i] =
          std::min(caps[i], std::sqrt(style.max_lateral_acceleration / (curvature * grade_factor)));
    }
  }
  return caps;
}

// v at each node: as fast as the caps allow, reached with at most `acceleration` and left
// with at most `deceleration` (forward and backward passes over v^2 = v0^2 + 2 a du).
std::vector<double> limit_speeds(const std::vector<double>& u, std::vector<double> v,
                                 double acceleration, double deceleration) {
  for (std::size_t i = 1; i < v.size(); ++i) {
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2.0 * acceleration * (u[i] - u[i - 1])));
  }
  for (std::size_t i = v.size() - 1; i-- > 0;) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * deceleration * (u[i + 1] - u[i])));
  }
  return v;
}

// Two zero-speed nodes in a row (stops closer than a profile step) would leave a cell the car
// cannot cross at constant acceleration; a node between them lets it speed up and brake there.
void split_standing_cells(SpeedProfile& profile, std::vector<double>& caps) {
  for (std::size_t i = 0; i + 1 < caps.size(); ++i) {
    if (caps[i] > 0.0 || caps[i + 1] > 0.0) continue;
    const auto at = static_cast<std::ptrdiff_t>(i + 1);
    profile.u.insert(profile.u.begin() + at, 0.5 * (profile.u[i] + profile.u[i + 1]));
    profile.stand_s.insert(profile.stand_s.begin() + at, 0.0);
    caps.insert(caps.begin() + at, std::numeric_limits<double>::infinity());
  }
}

// Forward from s = 0 to a stop at s_end, stopping and standing at every stop point on the way.
SpeedProfile forward_profile(const Route& route, double s_end, Scenario fallback,
                             const VehicleMotionOptions& options, std::uint64_t seed) {
  Random target_rng(Random::derive_seed(seed, kTargetStream));
  Random stop_rng(Random::derive_seed(seed, kStopStream));
  SpeedProfile profile;
  profile.u = profile_nodes(route, s_end, options.profile_step_m);
  std::vector<double> caps = speed_caps(route, profile.u, fallback, options, target_rng);
  profile.stand_s.assign(profile.u.size(), 0.0);
  caps.front() = caps.back() = 0.0;
  std::size_t node = 0;
  for (double stop : route.stop_points()) {
    if (stop >= s_end) break;
    while (profile.u[node] < stop - kNodeMerge) ++node;
    caps[node] = 0.0;
    profile.stand_s[node] = stop_rng.uniform(options.min_stop_s, options.max_stop_s);
  }
  split_standing_cells(profile, caps);
  profile.v = limit_speeds(profile.u, caps, options.max_acceleration, options.max_deceleration);
  return profile;
}

// Reversing `distance` [m]: accelerate, hold reverse_speed_mps if there is room, brake.
SpeedProfile reverse_profile(double distance, const VehicleMotionOptions& options) {
  const double a = options.reverse_acceleration;
  const double top = std::min(options.reverse_speed_mps, std::sqrt(a * distance));
  const double ramp = top * top / (2.0 * a);  // distance to reach the top speed [m]
  if (distance - 2.0 * ramp < kNodeMerge) {   // no room to hold it: accelerate, then brake
    return {{0.0, ramp, distance}, {0.0, top, 0.0}, {0.0, 0.0, 0.0}};
  }
  return {{0.0, ramp, distance - ramp, distance}, {0.0, top, top, 0.0}, {0.0, 0.0, 0.0, 0.0}};
}

// ---- the timeline ---------------------------------------------------------------------------

double drive_time(const SpeedProfile& profile) {
  Timeline timeline(0.0);
  timeline.drive(profile, 1.0);
  return timeline.end_time();
}

// Standing still, then, when asked, reversing to s = 0 and changing gear.
Timeline start_timeline(const VehicleMotionOptions& options) {
  const bool reverse_first = options.reverse_m > 0.0 && options.reverse_at_start;
  Timeline timeline(reverse_first ? options.reverse_m : 0.0);
  timeline.stand(options.start_standstill_s);
  if (reverse_first) {
    timeline.drive(reverse_profile(options.reverse_m, options), -1.0);
    timeline.stand(options.gear_change_s);
  }
  return timeline;
}

// Drives forwards to a stop at s_stop, changes gear and reverses, then stands to the end of the
// log. s_stop is where the full drive is when the reversal must begin, less the braking time;
// when braking earlier still makes the reversal end too late, the budget shrinks and it retries.
Timeline with_final_reversal(const Route& route, const Timeline& full_drive, Scenario fallback,
                             double duration, const VehicleMotionOptions& options,
                             std::uint64_t seed) {
  const SpeedProfile reverse = reverse_profile(options.reverse_m, options);
  double budget = duration - options.gear_change_s - drive_time(reverse);
  for (int attempt = 0; attempt < kReverseFitTries; ++attempt) {
    const Kinematics at_budget = full_drive.at(budget);
    const double s_stop = full_drive.at(budget - at_budget.s_dot / options.max_deceleration).s;
    if (full_drive.end_time() < budget || !(s_stop >= options.reverse_m && s_stop > 0.0)) {
      reject_argument(
          "vehicle motion: no room to drive forwards and then reverse {} m in {} s on a {} m "
          "route",
          options.reverse_m, duration, route.length());
    }
    Timeline timeline = start_timeline(options);
    timeline.drive(forward_profile(route, s_stop, fallback, options, seed), 1.0);
    timeline.stand(options.gear_change_s);
    timeline.drive(reverse, -1.0);
    if (timeline.end_time() <= duration) return timeline;
    budget -= timeline.end_time() - duration;
  }
  reject_argument("vehicle motion: could not fit reversing {} m into {} s", options.reverse_m,
                  duration);
}

Timeline plan_timeline(const Route& route, Scenario fallback, double duration,
                       const VehicleMotionOptions& options, std::uint64_t seed) {
  Timeline timeline = start_timeline(options);
  timeline.drive(forward_profile(route, route.length(), fallback, options, seed), 1.0);
  if (options.reverse_m > 0.0 && !options.reverse_at_start) {
    return with_final_reversal(route, timeline, fallback, duration, options, seed);
  }
  if (timeline.end_time() < duration) {
    reject_argument(
        "vehicle motion: the {} m route ends after {} s, the log needs {} s (see "
        "route_length_for)",
        route.length(), timeline.end_time(), duration);
  }
  return timeline;
}

// ---- body and state -------------------------------------------------------------------------

// Lateral and longitudinal acceleration [m/s^2] (see the header) that drive the body.
Eigen::Vector2d body_inputs(const Route& route, const Kinematics& k) {
  const double grade = route.grade_at(k.s);
  const double q = std::sqrt(1.0 + grade * grade);  // 3-D length per horizontal length
  return {k.s_dot * k.s_dot * route.curvature_at(k.s) * q,
          k.s_ddot * q + k.s_dot * k.s_dot * grade * route.grade_rate_at(k.s) / q};
}

// The body's filtered (lateral, longitudinal) acceleration and its rate of change.
struct Body {
  Eigen::Vector2d value = Eigen::Vector2d::Zero();  // [m/s^2]
  Eigen::Vector2d rate = Eigen::Vector2d::Zero();   // [m/s^3]
};

// One classical Runge-Kutta step of x'' = w^2 (u - x) - 2 zeta w x' with u at the start, middle
// and end of the step.
void advance_body(Body& body, const Eigen::Vector2d& u0, const Eigen::Vector2d& u_mid,
                  const Eigen::Vector2d& u1, double h, double w, double zeta) {
  const auto accel = [&](const Eigen::Vector2d& u, const Eigen::Vector2d& x,
                         const Eigen::Vector2d& v) {
    return Eigen::Vector2d(w * w * (u - x) - 2.0 * zeta * w * v);
  };
  const Eigen::Vector2d x = body.value, v = body.rate;
  const Eigen::Vector2d k1x = v, k1v = accel(u0, x, v);
  const Eigen::Vector2d k2x = v + 0.5 * h * k1v, k2v = accel(u_mid, x + 0.5 * h * k1x, k2x);
  const Eigen::Vector2d k3x = v + 0.5 * h * k2v, k3v = accel(u_mid, x + 0.5 * h * k2x, k3x);
  const Eigen::Vector2d k4x = v + h * k3v, k4v = accel(u1, x + h * k3x, k4x);
  body.value = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
  body.rate = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
}

struct Angle {
  double value = 0.0;  // [rad]
  double rate = 0.0;   // [rad/s]
};

// world_from_vehicle's rotation and V's angular velocity in V from the five factors of the header.
// For R = F1 ... F5 with F_i turning about a fixed axis, omega_V = sum_i (F_i+1 ... F5)^T omega_i.
void set_attitude(const RoutePoint& p, const Kinematics& k, const Body& body,
                  const VehicleMotionOptions& options, VehicleState& state) {
  const double g = p.grade, q = std::sqrt(1.0 + g * g);
  const double sideways = p.crossfall / q;  // tan(road roll)
  const double sideways_rate = p.crossfall_rate / q - p.crossfall * g * p.grade_rate / (q * q * q);
  const Angle yaw{p.heading_enu + options.sideslip_gain * body.value.x(),
                  k.s_dot * p.curvature + options.sideslip_gain * body.rate.x()};
  const Angle road_pitch{-std::atan(g), -k.s_dot * p.grade_rate / (q * q)};
  const Angle road_roll{std::atan(sideways), k.s_dot * sideways_rate / (1.0 + sideways * sideways)};
  const Angle body_pitch{-options.pitch_gain * body.value.y(), -options.pitch_gain * body.rate.y()};
  const Angle body_roll{options.roll_gain * body.value.x(), options.roll_gain * body.rate.x()};
  Eigen::Matrix3d right = Eigen::Matrix3d::Identity();  // F_i+1 ... F5
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  const auto add = [&](const Eigen::Vector3d& axis, const Angle& angle) {
    omega += right.transpose() * axis * angle.rate;
    right = Eigen::AngleAxisd(angle.value, axis).toRotationMatrix() * right;
  };
  add(Eigen::Vector3d::UnitX(), body_roll);
  add(Eigen::Vector3d::UnitY(), body_pitch);
  add(Eigen::Vector3d::UnitX(), road_roll);
  add(Eigen::Vector3d::UnitY(), road_pitch);
  add(Eigen::Vector3d::UnitZ(), yaw);
  state.world_from_vehicle.linear() = right;
  state.angular_velocity_vehicle = omega;
  state.yaw_rate = yaw.rate;
}

VehicleState make_state(const Route& route, const Kinematics& k, double time, const Body& body,
                        const VehicleMotionOptions& options) {
  const RoutePoint p = route.at(std::clamp(k.s, 0.0, route.length()));
  const double q = std::sqrt(1.0 + p.grade * p.grade);
  VehicleState state;
  state.time = time;
  state.arc_length = p.s;
  state.speed = k.s_dot * q;
  state.longitudinal_acceleration = k.s_ddot * q + k.s_dot * k.s_dot * p.grade * p.grade_rate / q;
  state.path_curvature = p.curvature / q;
  state.lateral_acceleration = state.speed * state.speed * state.path_curvature;
  state.heading_enu = p.heading_enu;
  const double c = std::cos(p.heading_enu), s = std::sin(p.heading_enu);
  const Eigen::Vector3d tangent(c, s, p.grade);  // d position / ds
  state.velocity_enu = k.s_dot * tangent;
  state.acceleration_enu =
      k.s_ddot * tangent +
      k.s_dot * k.s_dot * Eigen::Vector3d(-p.curvature * s, p.curvature * c, p.grade_rate);
  state.steering_angle = std::atan(options.wheelbase_m * p.curvature);
  set_attitude(p, k, body, options, state);
  state.world_from_vehicle.translation() = Eigen::Vector3d(p.x, p.y, p.z);
  state.straight = std::abs(state.speed) > kStraightMinSpeed &&
                   std::abs(state.path_curvature) < kStraightMaxCurvature;
  return state;
}

// States at k / rate_hz; the body is integrated in between on a step of at most kMaxFilterStep.
VehicleStates sample(const Route& route, const Timeline& timeline, double duration,
                     const VehicleMotionOptions& options) {
  const auto count = static_cast<std::size_t>(std::llround(duration * options.rate_hz)) + 1;
  const int substeps = static_cast<int>(std::ceil(1.0 / (options.rate_hz * kMaxFilterStep)));
  const double h = 1.0 / (options.rate_hz * substeps);
  const double w = 2.0 * kPi * options.suspension_frequency_hz;
  const auto input = [&](double t) { return body_inputs(route, timeline.at(t)); };
  Body body;  // every timeline starts at rest: level on the suspension
  VehicleStates states;
  states.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / options.rate_hz;
    states.push_back(make_state(route, timeline.at(t), t, body, options));
    if (i + 1 == count) break;
    Eigen::Vector2d u0 = input(t);
    for (int j = 0; j < substeps; ++j) {
      const double t0 = t + j * h;
      const Eigen::Vector2d u1 = input(t0 + h);
      advance_body(body, u0, input(t0 + 0.5 * h), u1, h, w, options.suspension_damping);
      u0 = u1;
    }
  }
  return states;
}

}  // namespace

void VehicleMotionOptions::Check() const {
  const OptionsCheck check("VehicleMotionOptions");
  // The body is integrated in 1 / (rate_hz * substeps) steps and every state is kept: outside
  // [1, 1000] Hz the substep count overflows or the states exhaust memory.
  check.in_range("rate_hz", rate_hz, 1.0, 1000.0);
  straight_style.Check();
  urban_style.Check();
  highway_style.Check();
  check.positive("max_acceleration", max_acceleration);
  check.positive("max_deceleration", max_deceleration);
  check.non_negative("min_stop_s", min_stop_s);
  check.ordered("min_stop_s", min_stop_s, "max_stop_s", max_stop_s);
  check.non_negative("start_standstill_s", start_standstill_s);
  check.non_negative("reverse_m", reverse_m);
  check.positive("reverse_speed_mps", reverse_speed_mps);
  check.positive("reverse_acceleration", reverse_acceleration);
  check.non_negative("gear_change_s", gear_change_s);
  check.positive("wheelbase_m", wheelbase_m);
  check.in_range("max_steering_angle", max_steering_angle, 0.0, kPi / 2.0, Bounds::kOpen);
  check.finite("roll_gain", roll_gain);
  check.finite("pitch_gain", pitch_gain);
  check.finite("sideslip_gain", sideslip_gain);
  check.positive("suspension_frequency_hz", suspension_frequency_hz);
  check.positive("suspension_damping", suspension_damping);
  // The speed profile has a node every profile_step_m along the whole route.
  check.in_range("profile_step_m", profile_step_m, 0.01, 10.0);
}

const DrivingStyle& driving_style(const VehicleMotionOptions& options, Scenario road_kind) {
  switch (road_kind) {
    case Scenario::kStraight:
      return options.straight_style;
    case Scenario::kUrban:
    case Scenario::kCity:  // an urban road (its route's section is kUrban)
      return options.urban_style;
    case Scenario::kHighway:
      return options.highway_style;
    case Scenario::kMixed:
      break;
  }
  reject_argument("vehicle motion: no driving style for road kind '{}'", to_string(road_kind));
}

double route_length_for(Scenario scenario, double duration_s, const VehicleMotionOptions& options) {
  options.Check();
  OptionsCheck("route_length_for").non_negative("duration_s", duration_s);
  const double max_speed =
      scenario == Scenario::kMixed
          ? std::max(options.urban_style.max_speed_mps, options.highway_style.max_speed_mps)
          : driving_style(options, scenario).max_speed_mps;
  return duration_s * max_speed + options.reverse_m + kRouteMargin;
}

VehicleStates simulate_vehicle_motion(const Route& route, Scenario scenario, double duration_s,
                                      const VehicleMotionOptions& options, std::uint64_t seed) {
  options.Check();
  if (!(duration_s > 0.0 && duration_s * options.rate_hz < kMaxSamples)) {
    reject_argument("vehicle motion: duration {} s must be > 0 and give < {} samples", duration_s,
                    kMaxSamples);
  }
  if (route.sections().empty() && scenario == Scenario::kMixed) {
    reject_argument(
        "vehicle motion: a mixed scenario needs a route with urban and highway sections");
  }
  const double max_curvature = route.max_abs_curvature(0.0, route.length());
  if (std::atan(options.wheelbase_m * max_curvature) > options.max_steering_angle) {
    reject_argument(
        "vehicle motion: the route's curvature {} 1/m needs {} deg of steering, above the "
        "limit of {} deg",
        max_curvature, deg_from_rad(std::atan(options.wheelbase_m * max_curvature)),
        deg_from_rad(options.max_steering_angle));
  }
  if (!(options.reverse_m < route.length())) {
    reject_argument("vehicle motion: cannot reverse {} m on a {} m route", options.reverse_m,
                    route.length());
  }
  const Timeline timeline = plan_timeline(route, scenario, duration_s, options, seed);
  return sample(route, timeline, duration_s, options);
}

VehicleStates simulate_recorded_motion(const Route& route, std::span<const double> times,
                                       std::span<const double> arc_lengths,
                                       const VehicleMotionOptions& options) {
  options.Check();
  if (times.size() < 2 || times.size() != arc_lengths.size() || times.front() != 0.0) {
    reject_argument("vehicle motion: a recorded pace needs >= 2 times from 0, one arc length each");
  }
  // As for a generated drive: a recording spanning years (a bad time stamp) must not exhaust
  // memory with its states.
  if (!(times.back() * options.rate_hz < kMaxSamples)) {
    reject_argument("vehicle motion: the recording's {} s give >= {} samples", times.back(),
                    kMaxSamples);
  }
  Timeline timeline(arc_lengths.front());
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double dt = times[i] - times[i - 1];
    const double ds = arc_lengths[i] - arc_lengths[i - 1];
    if (!(dt > 0.0) || !(ds >= 0.0) || arc_lengths[i] > route.length()) {
      reject_argument(
          "vehicle motion: recorded times must increase and arc lengths must not decrease "
          "or pass the route's end (at {} s)",
          times[i]);
    }
    if (ds > 0.0) {
      timeline.cruise(ds, dt);
    } else {
      timeline.stand(dt);
    }
  }
  const double max_curvature = route.max_abs_curvature(0.0, route.length());
  if (std::atan(options.wheelbase_m * max_curvature) > options.max_steering_angle) {
    reject_argument("vehicle motion: the route's curvature {} 1/m is beyond the steering limit",
                    max_curvature);
  }
  return sample(route, timeline, times.back(), options);
}

}  // namespace x2car::sim
