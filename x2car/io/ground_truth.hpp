// What the simulator knows to be true, written beside its data (DESIGN §6):
//
// `ground_truth.yaml`:
//   scenario: urban                 # the scenario's name
//   seed: 1                         # the seed the data was generated with
//   duration_s: 60                  # length of the log [s]
//   trajectory: trajectory.csv      # the vehicle trajectory side file, beside this one
//   vehicle_from_ins:               # one mapping per sensor: vehicle_from_<sensor>
//     x: 0.1                        #   t_V_S [m]
//     y: 0
//     z: 1.5
//     roll: 0                       #   R_V_S = Rz(yaw) Ry(pitch) Rx(roll) [rad] (DESIGN §1)
//     pitch: 0.01
//     yaw: -0.03
//
// `--mounting FILE.yaml` reads the same layout; there only the vehicle_from_* entries matter.
//
// `trajectory.csv` (the true vehicle motion, normally at 100 Hz), one header line and rows of
//   time,x,y,z,roll,pitch,yaw,vx,vy,vz,speed,yaw_rate,curvature,straight
// time [s]; x y z: origin of the vehicle frame V in ENU [m]; roll pitch yaw: world_from_vehicle =
// Rz(yaw) Ry(pitch) Rx(roll) [rad]; vx vy vz: velocity of V's origin in ENU [m/s]; speed: signed,
// along the path [m/s]; yaw_rate [rad/s] and curvature [1/m], positive turning left; straight:
// 1 on a straight stretch, else 0.
//
// Numbers are written shortest-round-trip: a written file reads back to the same values.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::io {

// A sensor's mounting vehicle_from_sensor, kept as the six numbers the file holds so that it
// round-trips exactly (an Isometry3d would go through euler_from_rotation on the way out).
struct SensorMounting {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // t_V_S, sensor origin in V [m]
  EulerAngles rotation;                                   // R_V_S as roll, pitch, yaw [rad]

  Eigen::Isometry3d vehicle_from_sensor() const;
};

SensorMounting mounting_from_transform(const Eigen::Isometry3d& vehicle_from_sensor);

// Mountings keyed by sensor name ("ins", "lidar", "radar", "camera"; other names are kept too).
using SensorMountings = std::map<std::string, SensorMounting>;

struct GroundTruth {
  std::string scenario;                 // e.g. "urban"
  std::uint64_t seed = 0;               // the simulator's seed
  double duration_s = 0.0;              // [s]
  std::string trajectory_file;          // side file name, relative to the YAML file's folder
  SensorMountings vehicle_from_sensor;  // written as vehicle_from_<name>
};

// The truth's vehicle_from_<sensor>, when it holds that sensor.
std::optional<SensorMounting> find_mounting(const GroundTruth& truth, const std::string& sensor);

// Throws std::invalid_argument for a sensor name that is empty or not [A-Za-z0-9_].
std::string format_ground_truth(const GroundTruth& truth);
void write_ground_truth(const std::filesystem::path& path, const GroundTruth& truth);

// Every top-level key is required (scenario, seed, duration_s, trajectory); any number of
// vehicle_from_<sensor> mappings, each with x y z roll pitch yaw. Unknown top-level keys are
// ignored. InputError names the file, the line and the key (e.g. "vehicle_from_lidar.pitch").
GroundTruth read_ground_truth(const std::filesystem::path& path);
GroundTruth parse_ground_truth(std::string_view text, const std::string& source_name);

// The `--mounting FILE.yaml` form: only vehicle_from_<sensor> mappings are read (at least one);
// the other keys may be present or not.
SensorMountings read_mountings(const std::filesystem::path& path);
SensorMountings parse_mountings(std::string_view text, const std::string& source_name);

// ---- trajectory side file --------------------------------------------------------------------

constexpr std::string_view kTrajectoryCsvHeader =
    "time,x,y,z,roll,pitch,yaw,vx,vy,vz,speed,yaw_rate,curvature,straight";

// One row of trajectory.csv: the fields of sim::VehicleState that the file records.
struct TrajectoryRow {
  double time = 0.0;  // [s]
  Eigen::Isometry3d world_from_vehicle = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();  // of V's origin [m/s]
  double speed = 0.0;                                      // signed [m/s]
  double yaw_rate = 0.0;                                   // [rad/s], positive left
  double curvature = 0.0;                                  // [1/m], positive left
  bool straight = false;
};

std::string format_trajectory_csv(std::span<const TrajectoryRow> rows);
void write_trajectory_csv(const std::filesystem::path& path, std::span<const TrajectoryRow> rows);

// Requires exactly kTrajectoryCsvHeader; InputError naming file, line and field otherwise, for
// wrong field counts, non-numbers, a straight flag other than 0/1 and non-increasing times.
std::vector<TrajectoryRow> read_trajectory_csv(const std::filesystem::path& path);
std::vector<TrajectoryRow> parse_trajectory_csv(std::string_view text,
                                                const std::string& source_name);

}  // namespace x2car::io
