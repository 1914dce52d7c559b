// The simulated car's true motion: what every sensor model samples, and what the ground-truth
// trajectory file records.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace x2car::sim {

struct VehicleState {
  double time = 0.0;  // [s] since the start of the log
  // The vehicle frame V (x forward, y left, z up; origin on the road under the rear axle) in the
  // local ENU world: p_world = world_from_vehicle * p_vehicle. Its rotation holds the heading, the
  // road's grade and crossfall, and the body's roll and pitch on its suspension.
  Eigen::Isometry3d world_from_vehicle = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();              // of V's origin [m/s]
  Eigen::Vector3d angular_velocity_vehicle = Eigen::Vector3d::Zero();  // of V, in V [rad/s]
  double speed = 0.0;                      // signed, along the path: negative when reversing [m/s]
  double longitudinal_acceleration = 0.0;  // d(speed)/dt [m/s^2]
  double lateral_acceleration = 0.0;       // speed^2 * path curvature, positive left [m/s^2]
  double yaw_rate = 0.0;                   // [rad/s], positive turning left
  double path_curvature = 0.0;             // of the driven path [1/m], positive left
  double heading_enu = 0.0;  // direction of the path's tangent, counter-clockwise from east [rad]
  bool straight = false;     // moving faster than 1 m/s on a path with |curvature| < 1e-4 1/m
  // Added for the motion model (sim/vehicle_motion.hpp):
  Eigen::Vector3d acceleration_enu = Eigen::Vector3d::Zero();  // of V's origin [m/s^2]
  double arc_length = 0.0;      // horizontal distance along the route from its start [m]
  double steering_angle = 0.0;  // front wheel of the kinematic bicycle, positive left [rad]
};

using VehicleStates = std::vector<VehicleState>;

}  // namespace x2car::sim
