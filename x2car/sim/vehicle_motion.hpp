// The simulated car's motion along a route (DESIGN §4): a kinematic bicycle referenced at the rear
// axle, whose reference point follows the route exactly, driven with a speed profile (accelerate,
// cruise, brake for curves and stops, stand), with body roll and pitch on the suspension and an
// optional small sideslip in turns.
//
// Attitude, with the angles of rotation.hpp (R = Rz(yaw) Ry(pitch) Rx(roll); positive pitch tilts
// x down, positive roll lowers the right side):
//   world_from_vehicle = Rz(heading + sideslip) * Ry(road_pitch) Rx(road_roll)
//                                               * Ry(body_pitch) Rx(body_roll)
//   road_pitch = -atan(grade)                     uphill lifts the nose: negative pitch
//   road_roll  = atan(crossfall / sqrt(1 + grade^2))   so that V's z axis is the road's normal
//   body_roll  =  roll_gain  * lateral acceleration      a left turn (> 0) lowers the right side:
//                                                        the body rolls outwards, roll > 0
//   body_pitch = -pitch_gain * longitudinal acceleration braking (< 0) dips the nose: pitch > 0
//   sideslip   = sideslip_gain * lateral acceleration   the nose points into the turn
// The accelerations that drive roll, pitch and sideslip pass through the suspension: a damped
// second-order response (suspension_frequency_hz, suspension_damping), so the body lags the
// manoeuvre and its angular velocity stays continuous; in steady state it equals the gain times
// the acceleration.
//
// Speeds and accelerations along the path are 3-D: speed = |velocity_enu| (signed), and
// path_curvature = d heading / d(3-D arc length) = plan curvature / sqrt(1 + grade^2), so that
// yaw of the path = speed * path_curvature and lateral_acceleration = speed^2 * path_curvature.
// yaw_rate is the rate of heading + sideslip (the Rz factor above): speed * path_curvature plus the
// sideslip's rate. heading_enu is the path's tangent, which the car faces also when reversing.
//
// Speed profile: the rear axle drives the route's plan at a speed that reaches each stretch's
// cruise target (a 3-D speed) with <= max_acceleration, brakes with <= max_deceleration so that
// curves stay within the lateral limit and the car stops at every stop point, stands there
// min_stop_s..max_stop_s, and stops at the end of the route.
#pragma once

#include <cstdint>
#include <span>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/scenario.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

struct VehicleMotionOptions {
  double rate_hz = 100.0;  // samples per second [Hz]

  // How the car is driven on each kind of road (see default_driving_style for the defaults).
  DrivingStyle straight_style = default_driving_style(Scenario::kStraight);  // 50-70 km/h
  DrivingStyle urban_style = default_driving_style(Scenario::kUrban);        // 20-50 km/h
  DrivingStyle highway_style = default_driving_style(Scenario::kHighway);    // 80-120 km/h

  double max_acceleration = 2.0;  // speeding up [m/s^2]
  double max_deceleration = 3.0;  // braking for curves, stops and lower targets [m/s^2]
  double min_stop_s = 2.0;        // standing time at a stop point, drawn in [min, max] [s]
  double max_stop_s = 5.0;        // [s]

  // For tests of what calibrators reject: standing still at the start, and reversing.
  double start_standstill_s = 0.0;  // [s] standing before anything else
  double reverse_m = 0.0;           // distance driven backwards along the route [m]; 0 = none
  // Reverse to s = 0 right after the standstill; else at the end: stop, reverse, stand to the end.
  bool reverse_at_start = false;
  double reverse_speed_mps = 1.5;     // top speed when reversing, horizontal [m/s]
  double reverse_acceleration = 1.0;  // and its acceleration and braking [m/s^2]
  double gear_change_s = 1.0;         // standing between reversing and driving forwards [s]

  // Kinematic bicycle: steering = atan(wheelbase * plan curvature). Routes that would need more
  // than max_steering_angle are rejected (a car cannot follow them).
  double wheelbase_m = 2.8;                        // [m]
  double max_steering_angle = rad_from_deg(35.0);  // front wheel [rad]

  // Body on its suspension and tyres.
  double roll_gain = rad_from_deg(0.5);   // body roll per lateral acceleration [rad / (m/s^2)]
  double pitch_gain = rad_from_deg(0.4);  // nose dip per deceleration [rad / (m/s^2)]
  double sideslip_gain = 0.0;  // body yaw into the turn per lateral acceleration [rad / (m/s^2)]
  double suspension_frequency_hz = 1.5;  // natural frequency of the body's response [Hz], > 0
  double suspension_damping = 0.7;       // damping ratio of that response, > 0

  double profile_step_m = 0.5;  // spacing of the speed profile along the route [m]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// The driving style for a road kind (kStraight, kUrban, kHighway) from the options.
const DrivingStyle& driving_style(const VehicleMotionOptions& options, Scenario road_kind);

// A route length [m] that always lasts `duration_s` [s] of driving in the scenario with these
// options: the car never drives faster than the fastest cruise target of its road kinds.
double route_length_for(Scenario scenario, double duration_s, const VehicleMotionOptions& options);

// Samples the car's motion along `route` at t = k / rate_hz for k = 0 .. round(duration_s *
// rate_hz), both ends included. The road kind at s comes from the route's sections; where the
// route has none, `scenario` is the road kind (kMixed then throws). Throws std::invalid_argument on
// bad options, a route the car cannot steer, or a route too short to fill the duration (see
// route_length_for). The same arguments give the same speed profile on every platform; the states
// then depend only on libm's sin, cos and atan.
VehicleStates simulate_vehicle_motion(const Route& route, Scenario scenario, double duration_s,
                                      const VehicleMotionOptions& options, std::uint64_t seed);

// The car driving `route` at a recorded pace (`--trajectory`, recorded_drive.hpp): at times[i]
// [s] (from 0, increasing) it is at arc_lengths[i] [m] (non-decreasing, within the route), at
// constant speed in between; sampled at options.rate_hz to times.back(). The body's roll and pitch
// follow the accelerations as in simulate_vehicle_motion. Throws std::invalid_argument on bad
// input or a route the car cannot steer.
VehicleStates simulate_recorded_motion(const Route& route, std::span<const double> times,
                                       std::span<const double> arc_lengths,
                                       const VehicleMotionOptions& options);

}  // namespace x2car::sim
