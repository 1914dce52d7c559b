// The one test-data factory of the tests and benches (STYLE.md: "test data is synthesised by one
// shared generator"): every simulated drive they use is described here, from the simulator's
// options, and built by the simulator itself. Built into the x2car_test_support library.
//
//   simulated_drive        the options of a simulated drive (scenario, duration, seed, sensors)
//   SimulatedLidarDrive    a simulated drive and its LiDAR, sweeps made on demand
//   urban_radar_drive      a simulated urban drive with its radar scene (cached per seed)
//   radar_scans / radar_detections   that drive seen by a radar at a chosen yaw
//   constructed_radar_drive          an exact straight drive past chosen radar targets
//   straight_drive         constructed vehicle truth: level, straight, constant speed
//   world_drive            a route, the car's motion along it and the world around it
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "x2car/io/ground_truth.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/sim/radar_model.hpp"
#include "x2car/sim/radar_scene.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/vehicle_state.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim {
class LidarSimulator;
}

namespace x2car::sim::testing {

// ---- simulated drives ----------------------------------------------------------------------

// The options of a simulated drive: everything else at the simulator's defaults.
SimulationOptions simulated_drive(Scenario scenario, double duration_s, std::uint64_t seed,
                                  std::vector<std::string> sensors = {"ins"});

// As simulated_drive, with a LiDAR of `beams` beams (32, 64 or 128) among the sensors.
SimulationOptions simulated_lidar_drive(Scenario scenario, double duration_s, int beams,
                                        std::uint64_t seed,
                                        std::vector<std::string> sensors = {"lidar"});

// A simulated drive and its LiDAR, whose sweeps are made when asked for (thread-safe), as a folder
// of files would be read. Movable; the LiDAR refers to parts that move with it.
class SimulatedLidarDrive {
 public:
  explicit SimulatedLidarDrive(const SimulationOptions& drive);
  SimulatedLidarDrive(SimulatedLidarDrive&&) noexcept;
  SimulatedLidarDrive& operator=(SimulatedLidarDrive&&) noexcept;
  ~SimulatedLidarDrive();

  const Simulation& simulation() const;
  const LidarSimulator& lidar() const;
  const io::SensorMounting& truth() const;  // the LiDAR's true mounting
  std::vector<double> sweep_times() const;  // start time of every sweep [s]

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
};

// ---- radar -----------------------------------------------------------------------------------

// A simulated drive with its radar scene, shared by every mounting tried on it.
struct RadarDrive {
  Simulation simulation;
  RadarScene scene;
};

// An urban drive of `duration_s` and its default radar scene (scene seed: seed + 1000), made once
// per (seed, duration) and kept for the process (tests try many mountings on one drive).
const RadarDrive& urban_radar_drive(std::uint64_t seed, double duration_s = 60.0);

// The radar on the front bumper, 3.6 m ahead of the rear axle and 0.3 m left of the centre line.
inline const Eigen::Vector3d kRadarLeverArm{3.6, 0.3, 0.5};

// The drive seen by a radar at kRadarLeverArm, yawed by `yaw_deg` [deg] (no roll or pitch).
std::vector<RadarScan> radar_scans(const RadarDrive& drive, double yaw_deg,
                                   const RadarOptions& radar, std::uint64_t seed);
// Their detections, as a radar reader returns them.
std::vector<io::RadarDetection> radar_detections(const RadarDrive& drive, double yaw_deg,
                                                 const RadarOptions& radar, std::uint64_t seed);

// A plausible place on the car for a radar facing `yaw_deg` [deg]: where the ray from the middle
// of the car's outline (x from -1.0 m, the rear bumper, to 3.7 m, the front one; y within
// +-0.95 m) in that direction leaves it, 0.5 m up: the front bumper for 0 deg, a corner for 25 deg,
// the middle of a side for 90 deg, the rear bumper for 180 deg.
Eigen::Vector3d radar_lever_arm_facing(double yaw_deg);

// The drive seen by a radar at `lever_arm` (vehicle frame [m]) yawed by `yaw_deg` [deg].
std::vector<RadarScan> radar_scans_at(const RadarDrive& drive, const Eigen::Vector3d& lever_arm,
                                      double yaw_deg, const RadarOptions& radar,
                                      std::uint64_t seed);
std::vector<io::RadarDetection> radar_detections_at(const RadarDrive& drive,
                                                    const Eigen::Vector3d& lever_arm,
                                                    double yaw_deg, const RadarOptions& radar,
                                                    std::uint64_t seed);

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

struct ConstructedRadarDrive {
  std::vector<io::InsRecord> ins;
  std::vector<io::RadarDetection> detections;
};

// The car drives straight east at `speed` [m/s] for `duration_s`, INS at 100 Hz (mounted without
// rotation), radar scans at 14 Hz, radar at yaw `radar_yaw` [rad] and kRadarLeverArm; the
// detections are exact (no noise, no clutter).
ConstructedRadarDrive constructed_radar_drive(double speed, double duration_s, double radar_yaw,
                                              const std::vector<ConstructedTarget>& targets);

// A plausible lever arm [m] of a radar yawed `yaw_deg` [deg] on the car of sim::radar_positions:
// the front bumper (kRadarLeverArm) within 10 deg of ahead, a front corner up to 120 deg (left
// for positive yaws), a rear corner up to 165 deg, the rear bumper beyond.
Eigen::Vector3d radar_lever_arm_for_yaw(double yaw_deg);

// The drive seen by a radar at radar_lever_arm_for_yaw(yaw_deg), yawed by `yaw_deg` [deg], as a
// radar reader returns its detections (without track ids when !radar.track_ids).
std::vector<io::RadarDetection> radar_detections_facing(const RadarDrive& drive, double yaw_deg,
                                                        const RadarOptions& radar,
                                                        std::uint64_t seed);

// ---- constructed vehicle truth ---------------------------------------------------------------

// Level straight drive at constant `speed` [m/s] along `heading_enu` [rad], from `start` (ENU [m])
// at time 0, sampled at `rate_hz` for `duration_s` (both ends included): no yaw rate, no pitch.
VehicleStates straight_drive(double duration_s, double speed, double heading_enu,
                             double rate_hz = 100.0,
                             const Eigen::Vector3d& start = Eigen::Vector3d::Zero());

// ---- a drive's world ----------------------------------------------------------------------

// A route, the car's motion along it and the world generated around them, as the simulator makes
// them for a drive (no sensors).
struct WorldDrive {
  Route route;
  VehicleStates states;
  World world;
};
WorldDrive world_drive(Scenario scenario, double duration_s, std::uint64_t seed,
                       const WorldOptions& options = {});

}  // namespace x2car::sim::testing
