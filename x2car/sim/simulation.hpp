// One simulated drive: a route and the car's motion on it, the sensors' mountings (drawn or given)
// and their data, and the ground truth that goes with them (DESIGN §4). `x2car simulate` is this
// plus write_simulation.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/io/ground_truth.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/sim/ins_model.hpp"
#include "x2car/sim/lidar_writer.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/scenario.hpp"
#include "x2car/sim/vehicle_motion.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim {

// The sensors the simulator models so far.
std::vector<std::string> simulated_sensor_names();  // {"ins", "lidar"}

struct SimulationOptions {
  Scenario scenario = Scenario::kUrban;
  double duration_s = 60.0;                    // [s] of driving, > 0
  std::uint64_t seed = 1;                      // every random draw follows from it
  std::vector<std::string> sensors = {"ins"};  // a subset of simulated_sensor_names()
  // Mountings that replace the drawn ones, by sensor name (`--mounting FILE.yaml`).
  io::SensorMountings mountings;
  RouteOptions route;
  VehicleMotionOptions motion;
  InsOptions ins;      // InsOptions::rtk() by default
  WorldOptions world;  // the 3-D world, made when a sensor that sees it ("lidar") is simulated
  LidarOptions lidar;  // 64 beams at 10 Hz by default
  LidarFileFormat lidar_format = LidarFileFormat::kPcd;  // lidar/ as PCD, KITTI .bin or both
  double start_unix_time = io::kDefaultStartUnixTime;    // UTC of the log's time 0 [s]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct Simulation {
  io::GroundTruth truth;
  VehicleStates states;        // the car's true motion at motion.rate_hz
  std::vector<InsSample> ins;  // empty unless "ins" was simulated
  World world;                 // empty unless "lidar" was simulated
  // Set when "lidar" was simulated. Its sweeps are made while write_simulation writes them, so
  // that a long drive never holds them all in memory.
  std::optional<LidarOutput> lidar;
  double start_unix_time = 0.0;  // UTC of time 0 [s]
};

// A plausible mounting for a sensor of a real car, drawn from `random`: yaw within +-5 deg, pitch
// and roll within +-3 deg, and a lever arm where that sensor usually sits.
io::SensorMounting draw_mounting(const std::string& sensor, Random& random);

Simulation simulate(const SimulationOptions& options);

// Writes the simulation as the folder layout of docs/formats.md:
//   ground_truth.yaml, trajectory.csv, ins/novatel_enu.csv, ins/ins.csv, lidar/ (lidar_writer.hpp)
// Creates the folder; InputError when it cannot be written.
void write_simulation(const Simulation& simulation, const std::filesystem::path& out_dir);

}  // namespace x2car::sim
