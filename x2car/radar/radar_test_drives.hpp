// Test data for the radar calibrator's tests: simulated urban drives with their radar scene, and a
// constructed straight drive past chosen targets whose detections are exact (no noise, no
// clutter), for the geometry of the position method.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "x2car/core/extrinsic.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/sim/radar_model.hpp"
#include "x2car/sim/radar_scene.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car::radar::testing {

// One urban drive with its radar scene, shared by every mounting tried on it.
struct Drive {
  sim::Simulation simulation;
  sim::RadarScene scene;
};

inline const Drive& urban_drive(std::uint64_t seed, double duration_s = 60.0) {
  static std::map<std::pair<std::uint64_t, double>, Drive> drives;
  auto found = drives.find({seed, duration_s});
  if (found == drives.end()) {
    sim::SimulationOptions options;
    options.scenario = sim::Scenario::kUrban;
    options.duration_s = duration_s;
    options.seed = seed;
    Drive drive;
    drive.simulation = sim::simulate(options);
    drive.scene = sim::generate_radar_scene(drive.simulation.states, {}, seed + 1000);
    found = drives.emplace(std::pair{seed, duration_s}, std::move(drive)).first;
  }
  return found->second;
}

// The radar on the front bumper, 3.6 m ahead of the rear axle and 0.3 m left of the centre line.
inline const Eigen::Vector3d kLeverArm{3.6, 0.3, 0.5};

inline std::vector<io::RadarDetection> radar_detections(const Drive& drive, double yaw_deg,
                                                        const sim::RadarOptions& radar,
                                                        std::uint64_t seed) {
  const Eigen::Isometry3d vehicle_from_radar = make_transform(
      EulerAngles{.roll = 0.0, .pitch = 0.0, .yaw = rad_from_deg(yaw_deg)}, kLeverArm);
  const std::vector<sim::RadarScan> scans =
      sim::simulate_radar(drive.simulation.states, vehicle_from_radar, drive.scene, radar, seed);
  return sim::radar_measurements(scans);
}

// A target of the constructed drive: at `position` (world, the car starts at the origin heading
// east) at time 0, moving with `velocity`, reported under `track_id` while `visible_from` <= t <=
// `visible_to` and its range is within [min_range, max_range].
struct ConstructedTarget {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // [m]
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // [m/s]
  int track_id = 0;
  double visible_from = 0.0;  // [s]
  double visible_to = 1e9;    // [s]
  double min_range = 5.0;     // [m]
  double max_range = 70.0;    // [m]
};

struct ConstructedDrive {
  std::vector<io::InsRecord> ins;
  std::vector<io::RadarDetection> detections;
};

// The car drives straight east at `speed` [m/s] for `duration_s`, INS at 100 Hz (mounted without
// rotation), radar scans at 14 Hz, radar at yaw `radar_yaw` [rad] and kLeverArm.
inline ConstructedDrive constructed_drive(double speed, double duration_s, double radar_yaw,
                                          const std::vector<ConstructedTarget>& targets) {
  ConstructedDrive drive;
  for (int k = 0; k * 0.01 <= duration_s; ++k) {
    io::InsRecord record;
    record.time = k * 0.01;
    record.position_enu = {speed * record.time, 0.0, 0.0};
    record.velocity_enu = {speed, 0.0, 0.0};
    drive.ins.push_back(record);
  }
  const Eigen::Vector2d lever = kLeverArm.head<2>();
  for (int k = 0; k / 14.0 <= duration_s; ++k) {
    const double t = k / 14.0;
    const Eigen::Vector2d radar_position = Eigen::Vector2d(speed * t, 0.0) + lever;
    const Eigen::Vector2d radar_velocity(speed, 0.0);
    for (const ConstructedTarget& target : targets) {
      if (t < target.visible_from || t > target.visible_to) continue;
      const Eigen::Vector2d relative = target.position + t * target.velocity - radar_position;
      const double range = relative.norm();
      if (range < target.min_range || range > target.max_range) continue;
      io::RadarDetection detection;
      detection.time = t;
      detection.track_id = target.track_id;
      detection.range = range;
      detection.azimuth = wrap_angle(std::atan2(relative.y(), relative.x()) - radar_yaw);
      detection.range_rate = relative.dot(target.velocity - radar_velocity) / range;
      detection.x = range * std::cos(detection.azimuth);
      detection.y = range * std::sin(detection.azimuth);
      drive.detections.push_back(detection);
    }
  }
  return drive;
}

}  // namespace x2car::radar::testing
