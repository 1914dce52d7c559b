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
  std::filesystem::path input;  // the INS log file, or the sensor's folder
};

struct DriveFolder {
  std::filesystem::path root;
  std::vector<DriveSensor> sensors;  // INS first, then LiDARs, radars, cameras, each by name
  std::optional<std::filesystem::path> ins_log;       // DIR/ins/novatel_enu.csv when present
  std::optional<std::filesystem::path> ground_truth;  // DIR/ground_truth.yaml when present
};

// InputError naming the folder when it is missing, not a folder, or holds no sensor; naming
// DIR/ins when it has no novatel_enu.csv.
DriveFolder find_drive_sensors(const std::filesystem::path& root);

}  // namespace x2car::io
