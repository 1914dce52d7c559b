// One simulated drive: a route and the car's motion on it, the sensors' mountings (drawn or given)
// and their data, and the ground truth that goes with them (DESIGN §4). `x2car simulate` is this
// plus write_simulation.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/camera_model.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/sim/camera_model.hpp"
#include "x2car/sim/camera_writer.hpp"
#include "x2car/sim/ins_model.hpp"
#include "x2car/sim/lidar_writer.hpp"
#include "x2car/sim/radar_model.hpp"
#include "x2car/sim/recorded_drive.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/scenario.hpp"
#include "x2car/sim/vehicle_motion.hpp"
#include "x2car/sim/world.hpp"
#include "x2car/sim/world_radar.hpp"

namespace x2car::sim {

// The sensors the simulator models so far: "ins", "lidar", "radar", "camera", then the named
// radars of radar_positions() ("radar_front", "radar_left", ...).
std::vector<std::string> simulated_sensor_names();

// Where a car carries its radars. "radar" is a front radar; a car with several names each by its
// place, "radar_<position>" (e.g. radar_front, radar_left, radar_rear), each drawn around its
// nominal yaw (draw_mounting) and written to its own folder. The positions, nominal yaws:
//   front 0 deg, front_left +25, front_right -25 (front corners, diagonal), left +90, right -90
//   (front corners, looking sideways: a drawn yaw covers 85-95 deg), rear 180, rear_left +135,
//   rear_right -135 (rear corners).
struct RadarPosition {
  std::string name;              // "front", "left", ...: the sensor is "radar_" + name
  double nominal_yaw_deg = 0.0;  // [deg]
};
std::vector<RadarPosition> radar_positions();
// Whether `sensor` is a radar ("radar" or "radar_<position>").
bool is_radar_sensor(const std::string& sensor);

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
  WorldOptions world;  // the 3-D world, made when a sensor that sees it (lidar, radar) is simulated
  LidarOptions lidar;  // 64 beams at 10 Hz by default
  LidarFileFormat lidar_format = LidarFileFormat::kPcd;  // lidar/ as PCD, KITTI .bin or both
  RadarOptions radar;  // ARS408-like by default; use RadarOptions::delphi_esr() with kDelphi
  WorldRadarOptions world_radar;      // how the world's objects become targets
  CameraOptions camera;               // intrinsics (the "kitti" preset)
  CameraRenderOptions camera_render;  // how its images are rendered (camera_render.hpp)
  io::RadarLayout radar_layout = io::RadarLayout::kConti;  // radar/ as Conti, Delphi or generic
  double start_unix_time = io::kDefaultStartUnixTime;      // UTC of the log's time 0 [s]
  // A recorded path to drive instead of a generated route (`--trajectory`): poses in a z-up world
  // (KITTI's through kitti_poses_to_z_up), times increasing. The drive lasts the recording, cut
  // to duration_s; the world is generated around it with the scenario's road (not kMixed).
  std::vector<StampedPose> recorded_path;
  // The file recorded_path was read from, or empty: when set, a recording that cannot be driven
  // (too short, too long, a jump) is an InputError naming this file rather than an
  // std::invalid_argument, since the fault is in the user's file, not in the options.
  std::string recorded_path_file;
  RecordedDriveOptions recorded;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct Simulation {
  io::GroundTruth truth;
  VehicleStates states;        // the car's true motion at motion.rate_hz
  std::vector<InsSample> ins;  // empty unless "ins" was simulated
  World world;                 // empty unless "lidar", "radar" or "camera" was simulated
  // Set when "lidar" was simulated. Its sweeps are made while write_simulation writes them, so
  // that a long drive never holds them all in memory.
  std::optional<LidarOutput> lidar;
  // Per simulated radar sensor ("radar", "radar_front", ...): one entry per scan with the
  // detections' truth.
  std::map<std::string, std::vector<RadarScan>> radars;
  io::RadarLayout radar_layout = io::RadarLayout::kConti;
  // Set when "camera" was simulated: its intrinsics (its mounting is in truth as "camera", that of
  // its body frame; camera_model.hpp).
  std::optional<core::CameraIntrinsics> camera;
  // Set with `camera`. Its frames are rendered while write_simulation writes them.
  std::optional<CameraOutput> camera_output;
  double start_unix_time = 0.0;  // UTC of time 0 [s]
};

// A plausible mounting for a sensor of a real car, drawn from `random`: yaw within +-5 deg of its
// nominal yaw (0, or a named radar's, radar_positions), pitch and roll within +-3 deg (a radar's
// within +-1 deg: it is aligned to the road when fitted), and a lever arm where that sensor
// usually sits (a named radar's at its corner or bumper). A camera's is that of its body frame
// (camera_model.hpp).
io::SensorMounting draw_mounting(const std::string& sensor, Random& random);

Simulation simulate(const SimulationOptions& options);

// Writes the simulation as the folder layout of docs/formats.md:
//   ground_truth.yaml, trajectory.csv, ins/novatel_enu.csv, ins/ins.csv, lidar/ (lidar_writer.hpp),
//   per radar sensor a folder named after it, radar/ or radar_left/ ... (io::write_radar in the
//   simulation's layout; emptied first, so that a rerun leaves no stale scans) and
//   <sensor>_truth.csv (radar_truth.csv, radar_left_truth.csv: each detection's source),
//   camera/intrinsics.yaml (ROS camera_info), camera/calib_cam_to_cam.txt (KITTI, camera 02),
//   camera/images/, camera/timestamps.txt (camera_writer.hpp) and camera/labels.csv
// Creates the folder; InputError when it cannot be written. `lidar_progress` follows the LiDAR's
// sweeps and `camera_progress` the camera's frames, the slow parts of a long drive.
void write_simulation(const Simulation& simulation, const std::filesystem::path& out_dir,
                      const SweepProgress& lidar_progress = {},
                      const FrameProgress& camera_progress = {});

// The radar detections' ground truth, one row per detection in the order of the radar's files:
//   time,track_id,source,object_id,moving,range,azimuth,range_rate
// time [s] on the drive's clock; source target | ghost | clutter; object_id the world object (a
// ghost's: its target's; -1 for clutter); moving 1 when the source moves over ground; range [m],
// azimuth [rad], range_rate [m/s] without noise.
constexpr const char* kRadarTruthFile = "radar_truth.csv";
// That file of radar sensor `sensor`: "<sensor>_truth.csv".
std::string radar_truth_file(const std::string& sensor);

// The camera's intrinsics in the drive's camera/ folder: a ROS camera_info YAML
// (io/camera_info_yaml.hpp) and a KITTI calib_cam_to_cam.txt (io/kitti_calib_cam.hpp) that holds
// it as camera kCameraKittiIndex, like KITTI raw's image_02.
constexpr const char* kCameraIntrinsicsFile = "intrinsics.yaml";
constexpr const char* kCameraKittiCalibFile = "calib_cam_to_cam.txt";
constexpr int kCameraKittiIndex = 2;
std::string format_radar_truth_csv(std::span<const RadarScan> scans);

}  // namespace x2car::sim
