// Constructed vehicle truth shared by the sensor-model tests (ins_model_test, radar_model_test,
// radar_scene_test): drives simple enough that the expected measurements follow by hand.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim::testing {

// Level straight drive at constant `speed` [m/s] along `heading_enu` [rad], from `start` (ENU [m])
// at time 0, sampled at `rate_hz` for `duration_s` (both ends included): no yaw rate, no pitch.
inline VehicleStates straight_drive(double duration_s, double speed, double heading_enu,
                                    double rate_hz = 100.0,
                                    const Eigen::Vector3d& start = Eigen::Vector3d::Zero()) {
  const Eigen::Vector3d direction(std::cos(heading_enu), std::sin(heading_enu), 0.0);
  VehicleStates states;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz)) + 1;
  for (int i = 0; i < n; ++i) {
    VehicleState s;
    s.time = i / rate_hz;
    s.world_from_vehicle =
        make_transform(EulerAngles{0, 0, heading_enu}, start + direction * speed * s.time);
    s.velocity_enu = direction * speed;
    s.speed = speed;
    s.heading_enu = heading_enu;
    s.straight = true;
    states.push_back(s);
  }
  return states;
}

}  // namespace x2car::sim::testing
