#include "x2car/sim/test_drives.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <utility>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/vehicle_motion.hpp"
#include "x2car/sim/world_scene.hpp"

namespace x2car::sim::testing {

SimulationOptions simulated_drive(Scenario scenario, double duration_s, std::uint64_t seed,
                                  std::vector<std::string> sensors) {
  SimulationOptions options;
  options.scenario = scenario;
  options.duration_s = duration_s;
  options.seed = seed;
  options.sensors = std::move(sensors);
  return options;
}

SimulationOptions simulated_lidar_drive(Scenario scenario, double duration_s, int beams,
                                        std::uint64_t seed, std::vector<std::string> sensors) {
  SimulationOptions options = simulated_drive(scenario, duration_s, seed, std::move(sensors));
  options.lidar.beams = beams;
  return options;
}

// The scene and the LiDAR refer to the simulation: the three live together on the heap, so the
// drive can move.
struct SimulatedLidarDrive::Parts {
  explicit Parts(const SimulationOptions& drive)
      : simulation(simulate(drive)),
        scene(simulation.world),
        lidar(scene, simulation.states, truth().vehicle_from_sensor(), simulation.lidar->options,
              simulation.lidar->seed) {}

  const io::SensorMounting& truth() const {
    return simulation.truth.vehicle_from_sensor.at("lidar");
  }

  Simulation simulation;
  WorldScene scene;
  LidarSimulator lidar;
};

SimulatedLidarDrive::SimulatedLidarDrive(const SimulationOptions& drive)
    : parts_(std::make_unique<Parts>(drive)) {}
SimulatedLidarDrive::SimulatedLidarDrive(SimulatedLidarDrive&&) noexcept = default;
SimulatedLidarDrive& SimulatedLidarDrive::operator=(SimulatedLidarDrive&&) noexcept = default;
SimulatedLidarDrive::~SimulatedLidarDrive() = default;

const Simulation& SimulatedLidarDrive::simulation() const { return parts_->simulation; }
const LidarSimulator& SimulatedLidarDrive::lidar() const { return parts_->lidar; }
const io::SensorMounting& SimulatedLidarDrive::truth() const { return parts_->truth(); }

std::vector<double> SimulatedLidarDrive::sweep_times() const {
  std::vector<double> times;
  for (std::size_t i = 0; i < parts_->lidar.sweep_count(); ++i) {
    times.push_back(parts_->lidar.sweep_start_time(i));
  }
  return times;
}

const RadarDrive& urban_radar_drive(std::uint64_t seed, double duration_s) {
  static std::mutex mutex;
  static std::map<std::pair<std::uint64_t, double>, RadarDrive> drives;
  const std::lock_guard lock(mutex);
  auto found = drives.find({seed, duration_s});
  if (found == drives.end()) {
    RadarDrive drive;
    drive.simulation = simulate(simulated_drive(Scenario::kUrban, duration_s, seed));
    drive.scene = generate_radar_scene(drive.simulation.states, {}, seed + 1000);
    found = drives.emplace(std::pair{seed, duration_s}, std::move(drive)).first;
  }
  return found->second;
}

std::vector<RadarScan> radar_scans(const RadarDrive& drive, double yaw_deg,
                                   const RadarOptions& radar, std::uint64_t seed) {
  const Eigen::Isometry3d vehicle_from_radar = make_transform(
      EulerAngles{.roll = 0.0, .pitch = 0.0, .yaw = rad_from_deg(yaw_deg)}, kRadarLeverArm);
  return simulate_radar(drive.simulation.states, vehicle_from_radar, drive.scene, radar, seed);
}

std::vector<io::RadarDetection> radar_detections(const RadarDrive& drive, double yaw_deg,
                                                 const RadarOptions& radar, std::uint64_t seed) {
  return radar_measurements(radar_scans(drive, yaw_deg, radar, seed));
}

Eigen::Vector3d radar_lever_arm_facing(double yaw_deg) {
  constexpr double kRear = -1.0;
  constexpr double kFront = 3.7;
  constexpr double kHalfWidth = 0.95;
  const double centre = 0.5 * (kRear + kFront);
  const double dx = std::cos(rad_from_deg(yaw_deg));
  const double dy = std::sin(rad_from_deg(yaw_deg));
  // The smallest positive distance at which the ray meets an edge of the outline.
  double distance = 1e9;
  if (std::abs(dx) > 1e-12)
    distance = std::min(distance, (dx > 0 ? kFront - centre : centre - kRear) / std::abs(dx));
  if (std::abs(dy) > 1e-12) distance = std::min(distance, kHalfWidth / std::abs(dy));
  return {centre + distance * dx, distance * dy, 0.5};
}

std::vector<RadarScan> radar_scans_at(const RadarDrive& drive, const Eigen::Vector3d& lever_arm,
                                      double yaw_deg, const RadarOptions& radar,
                                      std::uint64_t seed) {
  const Eigen::Isometry3d vehicle_from_radar = make_transform(
      EulerAngles{.roll = 0.0, .pitch = 0.0, .yaw = rad_from_deg(yaw_deg)}, lever_arm);
  return simulate_radar(drive.simulation.states, vehicle_from_radar, drive.scene, radar, seed);
}

std::vector<io::RadarDetection> radar_detections_at(const RadarDrive& drive,
                                                    const Eigen::Vector3d& lever_arm,
                                                    double yaw_deg, const RadarOptions& radar,
                                                    std::uint64_t seed) {
  return radar_measurements(radar_scans_at(drive, lever_arm, yaw_deg, radar, seed));
}

ConstructedRadarDrive constructed_radar_drive(double speed, double duration_s, double radar_yaw,
                                              const std::vector<ConstructedTarget>& targets) {
  ConstructedRadarDrive drive;
  for (int k = 0; k * 0.01 <= duration_s; ++k) {
    io::InsRecord record;
    record.time = k * 0.01;
    record.position_enu = {speed * record.time, 0.0, 0.0};
    record.velocity_enu = {speed, 0.0, 0.0};
    drive.ins.push_back(record);
  }
  const Eigen::Vector2d lever = kRadarLeverArm.head<2>();
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

Eigen::Vector3d radar_lever_arm_for_yaw(double yaw_deg) {
  const double side = yaw_deg < 0.0 ? -1.0 : 1.0;
  const double magnitude = std::abs(deg_from_rad(wrap_angle(rad_from_deg(yaw_deg))));
  if (magnitude <= 10.0) return kRadarLeverArm;
  if (magnitude <= 60.0) return {3.45, side * 0.7, 0.5};   // front corner, diagonal
  if (magnitude <= 120.0) return {3.2, side * 0.85, 0.5};  // front corner, sideways
  if (magnitude <= 165.0) return {-0.8, side * 0.7, 0.5};  // rear corner
  return {-0.95, 0.1, 0.5};                                // rear bumper
}

std::vector<io::RadarDetection> radar_detections_facing(const RadarDrive& drive, double yaw_deg,
                                                        const RadarOptions& radar,
                                                        std::uint64_t seed) {
  return radar_detections_at(drive, radar_lever_arm_for_yaw(yaw_deg), yaw_deg, radar, seed);
}

VehicleStates straight_drive(double duration_s, double speed, double heading_enu, double rate_hz,
                             const Eigen::Vector3d& start) {
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

WorldDrive world_drive(Scenario scenario, double duration_s, std::uint64_t seed,
                       const WorldOptions& options) {
  const VehicleMotionOptions motion;
  Route route = generate_route(scenario, route_length_for(scenario, duration_s, motion), seed);
  VehicleStates states = simulate_vehicle_motion(route, scenario, duration_s, motion, seed);
  World world = generate_world(route, scenario, states, options, seed);
  return {std::move(route), std::move(states), std::move(world)};
}

}  // namespace x2car::sim::testing
