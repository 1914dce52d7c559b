#include "x2car/sim/vehicle_motion.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/route.hpp"

namespace x2car::sim {
namespace {

constexpr double kKmh = 1.0 / 3.6;  // [m/s] per km/h

VehicleStates drive(Scenario scenario, double duration_s, std::uint64_t seed,
                    const VehicleMotionOptions& options = {}) {
  const Route route =
      generate_route(scenario, route_length_for(scenario, duration_s, options), seed);
  return simulate_vehicle_motion(route, scenario, duration_s, options, seed);
}

// A route from curvature knots and stop points on a given vertical profile.
Route custom_route(std::vector<CurvatureKnot> knots, std::vector<double> stops = {},
                   VerticalProfile profile = {}) {
  RoadPlan plan;
  plan.curvature = std::move(knots);
  plan.stop_points = std::move(stops);
  return Route(std::move(plan), std::move(profile));
}

// Flat: straight 150 m, a stop at 100 m, then a long arc of radius 40 m turning to `side`.
Route stop_then_arc(double side) {
  const double k = side / 40.0;
  return custom_route({{0.0, 0.0}, {150.0, 0.0}, {160.0, k}, {1500.0, k}}, {100.0});
}

bool identical(const VehicleState& a, const VehicleState& b) {
  return a.time == b.time && a.world_from_vehicle.matrix() == b.world_from_vehicle.matrix() &&
         a.velocity_enu == b.velocity_enu &&
         a.angular_velocity_vehicle == b.angular_velocity_vehicle && a.speed == b.speed &&
         a.longitudinal_acceleration == b.longitudinal_acceleration &&
         a.lateral_acceleration == b.lateral_acceleration && a.yaw_rate == b.yaw_rate &&
         a.path_curvature == b.path_curvature && a.heading_enu == b.heading_enu &&
         a.straight == b.straight && a.acceleration_enu == b.acceleration_enu &&
         a.arc_length == b.arc_length && a.steering_angle == b.steering_angle;
}

Eigen::Vector3d position(const VehicleState& state) {
  return state.world_from_vehicle.translation();
}

EulerAngles attitude(const VehicleState& state) {
  return euler_from_rotation(state.world_from_vehicle.linear());
}

// The largest heading change from the start [rad], unwrapped along the log.
double largest_turn(const VehicleStates& states) {
  double turned = 0.0, largest = 0.0;
  for (std::size_t k = 1; k < states.size(); ++k) {
    turned += angle_difference(states[k].heading_enu, states[k - 1].heading_enu);
    largest = std::max(largest, std::abs(turned));
  }
  return largest;
}

// The longest time [s] the car stands (speed exactly 0) after it first moved.
double longest_stop(const VehicleStates& states) {
  double longest = 0.0, since = -1.0;
  bool moved = false;
  for (const VehicleState& state : states) {
    moved = moved || state.speed != 0.0;
    if (!moved || state.speed != 0.0) {
      since = -1.0;
      continue;
    }
    if (since < 0.0) since = state.time;
    longest = std::max(longest, state.time - since);
  }
  return longest;
}

TEST(VehicleMotion, IsDeterministicAndSampledAtTheRate) {
  const VehicleStates a = drive(Scenario::kUrban, 60.0, 3);
  const VehicleStates b = drive(Scenario::kUrban, 60.0, 3);
  const VehicleStates c = drive(Scenario::kUrban, 60.0, 4);
  ASSERT_EQ(a.size(), 6001u);  // 0 .. 60 s at 100 Hz, both ends included
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(identical(a[k], b[k])) << "sample " << k;
    ASSERT_EQ(a[k].time, static_cast<double>(k) / 100.0);
  }
  EXPECT_GT((position(a.back()) - position(c.back())).norm(), 10.0);
}

TEST(VehicleMotion, UrbanStaysBelow50KmhStopsAndTurns) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const VehicleStates states = drive(Scenario::kUrban, 60.0, seed);
    for (const VehicleState& state : states) {
      ASSERT_GE(state.speed, 0.0);
      ASSERT_LE(state.speed, 50.0 * kKmh * (1.0 + 1e-6)) << "t " << state.time;
    }
    EXPECT_GE(longest_stop(states), 2.0) << "seed " << seed;  // a full stop at a stop line
    EXPECT_GT(largest_turn(states), rad_from_deg(85.0)) << "seed " << seed;  // a 90-degree turn
  }
}

TEST(VehicleMotion, HighwayStaysWithin80And120KmhAfterTheStart) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const VehicleStates states = drive(Scenario::kHighway, 600.0, seed);
    const auto cruising = std::find_if(
        states.begin(), states.end(), [](const VehicleState& s) { return s.speed >= 80.0 * kKmh; });
    ASSERT_NE(cruising, states.end());
    // From standstill at <= 2 m/s^2 (and a little more from the 3-D speed on a grade).
    EXPECT_GE(cruising->time, 80.0 * kKmh / 2.0 * 0.99);
    for (auto it = cruising; it != states.end(); ++it) {
      ASSERT_GE(it->speed, 80.0 * kKmh * (1.0 - 1e-4)) << "seed " << seed << " t " << it->time;
      ASSERT_LE(it->speed, 120.0 * kKmh * (1.0 + 1e-4)) << "seed " << seed << " t " << it->time;
    }
  }
}

TEST(VehicleMotion, AccelerationsStayWithinTheLimits) {
  const std::pair<Scenario, double> cases[] = {{Scenario::kStraight, 2.0},
                                               {Scenario::kUrban, 3.0},
                                               {Scenario::kHighway, 2.0},
                                               {Scenario::kMixed, 3.0}};
  for (const auto& [scenario, limit] : cases) {
    double largest = 0.0;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      for (const VehicleState& state : drive(scenario, 180.0, seed)) {
        ASSERT_LE(std::abs(state.lateral_acceleration), limit + 1e-9) << to_string(scenario);
        // 2 and 3 m/s^2 along the plan; the 3-D speed also changes where the grade does, by
        // speed^2 * grade * d(grade)/ds < (33 m/s)^2 * 0.06 * 0.0013 / m = 0.085 m/s^2.
        ASSERT_LE(state.longitudinal_acceleration, 2.0 + 0.1);
        ASSERT_GE(state.longitudinal_acceleration, -3.0 - 0.1);
        largest = std::max(largest, std::abs(state.lateral_acceleration));
      }
    }
    if (scenario == Scenario::kUrban) {
      EXPECT_GT(largest, 2.5);  // the turns reach the limit
    }
  }
}

// rotation.hpp: positive roll lowers the right side (the y axis rises), positive pitch tilts x
// down. In a left turn (lateral acceleration > 0) the body rolls outwards, to the right: roll > 0.
TEST(VehicleMotion, BodyRollsOutwardsAndDipsWhenBraking) {
  VehicleMotionOptions options;
  options.urban_style.min_speed_mps = 50.0 * kKmh;  // so that the arc's 3 m/s^2 sets the speed
  options.sideslip_gain = rad_from_deg(0.2);
  for (double side : {1.0, -1.0}) {
    const VehicleStates states =
        simulate_vehicle_motion(stop_then_arc(side), Scenario::kUrban, 60.0, options, 1);
    // Deep in the arc, at constant speed: steady state of the suspension.
    const auto turning = std::find_if(states.begin(), states.end(),
                                      [](const VehicleState& s) { return s.arc_length > 300.0; });
    ASSERT_NE(turning, states.end());
    EXPECT_EQ(turning->longitudinal_acceleration, 0.0);
    EXPECT_NEAR(turning->lateral_acceleration, side * 3.0, 1e-9);
    const double roll = attitude(*turning).roll;
    EXPECT_GT(side * roll, 0.0);
    EXPECT_NEAR(roll, options.roll_gain * turning->lateral_acceleration, 1e-4);
    EXPECT_GT(side * turning->world_from_vehicle.linear()(2, 1), 0.0);  // y axis rises (left turn)
    // Sideslip: the nose points into the turn, by sideslip_gain * lateral acceleration.
    const double sideslip = angle_difference(attitude(*turning).yaw, turning->heading_enu);
    EXPECT_NEAR(sideslip, options.sideslip_gain * turning->lateral_acceleration, 1e-6);
    EXPECT_GT(side * sideslip, 0.0);
  }
  // Braking for the stop at 3 m/s^2: the nose dips, pitch = +pitch_gain * 3 once settled.
  const VehicleStates states =
      simulate_vehicle_motion(stop_then_arc(1.0), Scenario::kUrban, 60.0, options, 1);
  const auto stopped = std::find_if(states.begin(), states.end(),
                                    [](const VehicleState& s) { return s.arc_length >= 100.0; });
  ASSERT_NE(stopped, states.end());
  const VehicleState& braking = *(stopped - 1);  // the last instant of braking
  EXPECT_NEAR(braking.longitudinal_acceleration, -3.0, 1e-9);
  EXPECT_NEAR(attitude(braking).pitch, options.pitch_gain * 3.0, 1e-3 * options.pitch_gain * 3.0);
  EXPECT_LT(attitude(states[100]).pitch, 0.0);  // accelerating from rest: the nose lifts
}

// Uphill pitches the nose up (negative pitch); a road rising to the left lifts the left side
// (positive roll); V's z axis is the road's normal.
TEST(VehicleMotion, GradeAndCrossfallTiltTheCar) {
  VerticalProfile profile;
  profile.grade_waves = {{0.05, 4000.0, 0.3}};
  profile.crossfall_waves = {{0.03, 3000.0, 0.5}};
  const Route route = custom_route({{0.0, 0.0}, {2000.0, 0.0}}, {}, profile);
  VehicleMotionOptions options;
  options.straight_style.min_stretch_m = options.straight_style.max_stretch_m = 1000.0;
  const VehicleStates states =
      simulate_vehicle_motion(route, Scenario::kStraight, 60.0, options, 1);
  int checked = 0;
  for (const VehicleState& state : states) {
    const RoutePoint road = route.at(state.arc_length);
    const Eigen::Matrix3d rotation = state.world_from_vehicle.linear();
    const Eigen::Vector3d along(std::cos(road.heading_enu), std::sin(road.heading_enu), road.grade);
    const Eigen::Vector3d across(-std::sin(road.heading_enu), std::cos(road.heading_enu),
                                 road.crossfall);
    const double body_accel = std::abs(state.longitudinal_acceleration);
    if (state.time < 25.0 || body_accel > 1e-3) continue;  // settled cruising only
    EXPECT_NEAR(attitude(state).pitch, -std::atan(road.grade), 2e-5);
    EXPECT_NEAR(attitude(state).roll, std::atan(road.crossfall / std::hypot(1.0, road.grade)),
                2e-5);
    EXPECT_NEAR(rotation.col(2).dot(along.normalized()), 0.0, 2e-5);
    EXPECT_NEAR(rotation.col(2).dot(across.normalized()), 0.0, 2e-5);
    ++checked;
  }
  for (const VehicleState& state : states) {  // no sideslip: the path's own yaw rate
    ASSERT_NEAR(state.yaw_rate, state.speed * state.path_curvature, 1e-12);
  }
  EXPECT_GT(checked, 1000);
  EXPECT_LT(attitude(states[3000]).pitch, -0.01);  // uphill here
  EXPECT_GT(attitude(states[3000]).roll, 0.01);    // left side higher here
}

// Every field against finite differences of the sampled poses, on a mixed drive with grade,
// crossfall, banked curves and sideslip. With piecewise-constant acceleration a trapezoid check is
// exact up to half the jump of the derivative within the step, hence the bounds.
TEST(VehicleMotion, StateFieldsAreConsistentWithThePoses) {
  VehicleMotionOptions options;
  options.sideslip_gain = rad_from_deg(0.2);
  const VehicleStates states = drive(Scenario::kMixed, 120.0, 2, options);
  const double dt = 0.01;
  double largest_climb = 0.0;
  for (std::size_t k = 0; k + 1 < states.size(); ++k) {
    const VehicleState &a = states[k], &b = states[k + 1];
    const Eigen::Vector3d velocity = (position(b) - position(a)) / dt;
    ASSERT_LT((velocity - 0.5 * (a.velocity_enu + b.velocity_enu)).norm(), 0.01) << a.time;
    const Eigen::Vector3d accel = (b.velocity_enu - a.velocity_enu) / dt;
    ASSERT_LT((accel - 0.5 * (a.acceleration_enu + b.acceleration_enu)).norm(),
              0.5 * (b.acceleration_enu - a.acceleration_enu).norm() + 1e-3)
        << a.time;
    const double speed_rate = (b.speed - a.speed) / dt;
    ASSERT_LE(
        std::abs(speed_rate - 0.5 * (a.longitudinal_acceleration + b.longitudinal_acceleration)),
        0.5 * std::abs(b.longitudinal_acceleration - a.longitudinal_acceleration) + 1e-3);
    const Eigen::Matrix3d step =
        a.world_from_vehicle.linear().transpose() * b.world_from_vehicle.linear();
    const Eigen::Vector3d omega = rotation_vector_from_rotation(step) / dt;
    const Eigen::Vector3d mean_omega =
        0.5 * (a.angular_velocity_vehicle + b.angular_velocity_vehicle);
    ASSERT_LT((omega - mean_omega).norm(),
              0.5 * (b.angular_velocity_vehicle - a.angular_velocity_vehicle).norm() + 1e-4)
        << a.time;
    // yaw_rate is the rate of heading + sideslip; the Euler yaw of the tilted body differs from
    // that by products of the small tilt angles (~1e-3 rad), and so do their rates.
    const double yaw_step = angle_difference(attitude(b).yaw, attitude(a).yaw) / dt;
    ASSERT_NEAR(yaw_step, 0.5 * (a.yaw_rate + b.yaw_rate),
                0.5 * std::abs(b.yaw_rate - a.yaw_rate) + 2e-3);
    largest_climb = std::max(largest_climb, std::abs(a.velocity_enu.z()));
  }
  EXPECT_GT(largest_climb, 0.1);  // the vertical velocity is really exercised
  for (const VehicleState& state : states) {
    ASSERT_NEAR(std::abs(state.speed), state.velocity_enu.norm(), 1e-12);
    ASSERT_NEAR(state.lateral_acceleration, state.speed * state.speed * state.path_curvature,
                1e-12);
    if (state.speed > 0.1) {
      // The bicycle steers by the plan curvature, path_curvature * sqrt(1 + grade^2).
      const double grade = state.velocity_enu.z() / state.velocity_enu.head<2>().norm();
      const double plan_curvature = state.path_curvature * std::hypot(1.0, grade);
      ASSERT_NEAR(angle_difference(std::atan2(state.velocity_enu.y(), state.velocity_enu.x()),
                                   state.heading_enu),
                  0.0, 1e-12);
      ASSERT_NEAR(state.steering_angle, std::atan(2.8 * plan_curvature), 1e-9);
    }
    ASSERT_EQ(state.straight, state.speed > 1.0 && std::abs(state.path_curvature) < 1e-4);
  }
}

TEST(VehicleMotion, StandsStillAtTheStartWhenAsked) {
  VehicleMotionOptions options;
  options.start_standstill_s = 3.0;
  const VehicleStates states = drive(Scenario::kUrban, 30.0, 5, options);
  for (const VehicleState& state : states) {
    if (state.time > 3.0) break;
    ASSERT_EQ(state.speed, 0.0) << state.time;
    ASSERT_EQ(state.velocity_enu, Eigen::Vector3d::Zero());
    ASSERT_EQ(position(state), position(states.front()));
  }
  EXPECT_GT(states[350].speed, 0.0);  // moving half a second later
}

// Reversing: negative speed, the car still facing along the route, the distance asked for.
TEST(VehicleMotion, ReversesAtTheEndOrTheStart) {
  VehicleMotionOptions options;
  options.reverse_m = 4.0;
  const VehicleStates at_end = drive(Scenario::kUrban, 60.0, 6, options);
  const auto first_back = std::find_if(at_end.begin(), at_end.end(),
                                       [](const VehicleState& s) { return s.speed < 0.0; });
  ASSERT_NE(first_back, at_end.end());
  EXPECT_GT(first_back->time, 45.0);  // the reversal closes the log
  for (auto it = first_back; it != at_end.end(); ++it) {
    ASSERT_LE(it->speed, 0.0);
    ASSERT_GE(it->speed, -options.reverse_speed_mps * 1.002);  // along the plan; 3-D on a grade
    if (it->speed < -0.1) {  // moving against the car's own x axis
      ASSERT_LT(it->velocity_enu.dot(it->world_from_vehicle.linear().col(0)), 0.0);
    }
  }
  EXPECT_NEAR((first_back - 1)->arc_length - at_end.back().arc_length, 4.0, 1e-9);
  EXPECT_EQ(at_end.back().speed, 0.0);

  options.reverse_at_start = true;
  const VehicleStates at_start = drive(Scenario::kUrban, 30.0, 6, options);
  EXPECT_EQ(at_start.front().arc_length, 4.0);
  EXPECT_LT(at_start[100].speed, 0.0);
  const auto forwards = std::find_if(at_start.begin(), at_start.end(),
                                     [](const VehicleState& s) { return s.speed > 0.0; });
  ASSERT_NE(forwards, at_start.end());
  EXPECT_NEAR((forwards - 1)->arc_length, 0.0, 1e-9);
  for (auto it = at_start.begin(); it != forwards; ++it) ASSERT_LE(it->speed, 0.0);
}

TEST(VehicleMotion, RejectsWhatItCannotDrive) {
  const VehicleMotionOptions options;
  const Route short_route = generate_route(Scenario::kUrban, 200.0, 1);
  try {
    simulate_vehicle_motion(short_route, Scenario::kUrban, 60.0, options, 1);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("route_length_for"));
  }
  // Radius 3 m needs atan(2.8 / 3) = 43 degrees of steering, more than 35.
  const Route tight = custom_route({{0.0, 0.0}, {10.0, 1.0 / 3.0}, {500.0, 0.0}});
  EXPECT_THROW(simulate_vehicle_motion(tight, Scenario::kUrban, 10.0, options, 1),
               std::invalid_argument);
  const Route plain = custom_route({{0.0, 0.0}, {2000.0, 0.0}});
  EXPECT_THROW(simulate_vehicle_motion(plain, Scenario::kMixed, 10.0, options, 1),
               std::invalid_argument);  // no sections to say which parts are urban
  EXPECT_THROW(simulate_vehicle_motion(plain, Scenario::kUrban, 0.0, options, 1),
               std::invalid_argument);
  VehicleMotionOptions bad;
  bad.rate_hz = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.urban_style.min_speed_mps = 20.0;  // above the maximum
  EXPECT_THROW(simulate_vehicle_motion(plain, Scenario::kUrban, 10.0, bad, 1),
               std::invalid_argument);
}

// The longest route (highway, ~21 km) at the full rate; its speed is measured in
// bench/sim_bench.cpp (BM_VehicleMotionTenMinutesHighway).
TEST(VehicleMotion, TenMinutesAt100HzGiveEveryState) {
  const VehicleStates states = drive(Scenario::kHighway, 600.0, 1);
  EXPECT_EQ(states.size(), 60001u);
}

}  // namespace
}  // namespace x2car::sim
