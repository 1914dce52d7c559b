// The sensors of a simulate-style drive folder (docs/formats.md, "A drive folder"), for `x2car
// calibrate all`: each sensor's name, kind and input, and the GNSS/INS log the radars and the
// camera take their motion from. Lists paths only; the calibrators read them.
//
//   DIR/ins/novatel_enu.csv                   the GNSS/INS ("ins")
//   DIR/lidar/, DIR/lidar_<place>/            LiDAR sweeps
//   DIR/radar/, DIR/radar_<place>/            radar files (front, left, rear, ...)
//   DIR/camera/, DIR/camera_<place>/          camera images + timestamps.txt + intrinsics.yaml
//   DIR/ground_truth.yaml                     the simulator's truth, when present
//
// Other entries are ignored. The sensor's name is its folder's: the child frame of its results.
//
// A user's own log is described by a manifest instead, DIR/x2car.yaml (docs/formats.md):
//   sensors:
//     gnss:         {type: ins, input: gnss/novatel_enu.csv}
//     lidar_top:    {type: lidar, input: lidar_top}
//     radar_left:   {type: radar, input: radar/left, lever_arm: [3.2, 0.8], nominal_yaw_deg: 90}
//     camera_front: {type: camera, input: front.mp4, intrinsics: front_camera_info.yaml}
//     lidar_roof:   {type: lidar, input: run.bag, topic: /velodyne_points}
//   ground_truth: ground_truth.yaml        (optional)
// Paths are relative to the manifest's folder. `topic` picks a bag's topic (any type).
//
// A bag itself (find_bag_sensors) is a drive too: one sensor per topic a calibrator reads.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/enum_names.hpp"

namespace x2car::io {

enum class SensorKind { kIns, kLidar, kRadar, kCamera };

constexpr std::array<EnumName<SensorKind>, 4> kSensorKindNames{{
    {SensorKind::kIns, "ins"},
    {SensorKind::kLidar, "lidar"},
    {SensorKind::kRadar, "radar"},
    {SensorKind::kCamera, "camera"},
}};

inline const char* to_string(SensorKind kind) { return enum_to_string(kSensorKindNames, kind); }

struct DriveSensor {
  std::string name;  // the folder's name: "ins", "lidar", "radar_front", ...
  SensorKind kind = SensorKind::kIns;
  std::filesystem::path input;  // the INS log file, or the sensor's folder (or a video)
  // From a manifest only:
  std::optional<std::filesystem::path> intrinsics;   // a camera's
  std::optional<std::array<double, 2>> lever_arm_m;  // a radar's x y on the car [m]
  std::optional<double> nominal_yaw_deg;             // a radar's yaw as designed [deg]
  std::optional<std::string> topic;                  // the input bag's topic
};

struct DriveFolder {
  std::filesystem::path root;
  std::vector<DriveSensor> sensors;  // INS first, then LiDARs, radars, cameras, each by name
  std::optional<std::filesystem::path> ins_log;  // the GNSS/INS sensor's log, when there is one
  std::optional<std::string> ins_topic;          // its topic, when the log is a bag
  std::optional<std::filesystem::path> ground_truth;  // DIR/ground_truth.yaml when present
};

// DIR/x2car.yaml when the folder has one (read_drive_manifest), else the folder's layout.
// InputError naming the folder when it is missing, not a folder, or holds no sensor; naming
// DIR/ins when it has no novatel_enu.csv.
DriveFolder find_drive_sensors(const std::filesystem::path& root);

// The sensors of a bag (io/bag.hpp): the GNSS/INS when it has one pose topic (Odometry,
// PoseStamped, INSPVA; else one NavSatFix), a LiDAR per PointCloud2 topic, a radar per RadarScan
// or RadarTracks topic, a camera per Image or CompressedImage topic; each named by its frame (its
// first message's header.frame_id; Odometry's child_frame_id; a camera's optical frame as its body
// frame, "camera_front_optical_frame" -> "camera_front"), as ROS and Autoware name the child
// frames, else (no frame, or one another sensor has) by its topic ("/sensing/lidar/top/points" ->
// "sensing_lidar_top_points"); its input the bag. InputError
// naming the bag when it holds no such topic, or several pose topics (calibrate ins --topic
// picks one).
DriveFolder find_bag_sensors(const std::filesystem::path& bag);

// A manifest. InputError naming the file, the line and the key (e.g. "sensors.radar_left.input")
// when it is not YAML, lacks `sensors`, a sensor lacks `type` or `input`, a type is unknown, an
// input or intrinsics file does not exist, a key is unknown (a typo), a key does not belong to the
// sensor's type, or two sensors are GNSS/INS (the radars and cameras take their motion from one).
DriveFolder read_drive_manifest(const std::filesystem::path& manifest);

constexpr const char* kDriveManifestName = "x2car.yaml";

}  // namespace x2car::io
