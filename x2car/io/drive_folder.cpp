#include "x2car/io/drive_folder.hpp"

#include <algorithm>
#include <system_error>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;

// The kind a folder's name says: "<kind>" or "<kind>_<place>".
std::optional<SensorKind> kind_of(const std::string& name) {
  for (const EnumName<SensorKind>& entry : kSensorKindNames) {
    const std::string kind = entry.name;
    if (name == kind || (name.size() > kind.size() + 1 && name.starts_with(kind + "_"))) {
      return entry.value;
    }
  }
  return std::nullopt;
}

}  // namespace

DriveFolder find_drive_sensors(const fs::path& root) {
  std::error_code error;
  if (!fs::is_directory(root, error)) {
    throw InputError(root.string(), "is not a folder (a drive folder as x2car simulate writes)");
  }
  DriveFolder drive;
  drive.root = root;
  for (const fs::directory_entry& entry : fs::directory_iterator(root, error)) {
    if (!entry.is_directory(error)) continue;
    const std::string name = entry.path().filename().string();
    const std::optional<SensorKind> kind = kind_of(name);
    if (!kind) continue;
    if (*kind == SensorKind::kIns) {
      if (name != "ins") continue;
      const fs::path log = entry.path() / "novatel_enu.csv";
      if (!fs::is_regular_file(log, error)) {
        throw InputError(entry.path().string(), "holds no novatel_enu.csv (the GNSS/INS log)");
      }
      drive.ins_log = log;
      drive.sensors.push_back({name, *kind, log});
    } else {
      drive.sensors.push_back({name, *kind, entry.path()});
    }
  }
  if (error) throw InputError(root.string(), "cannot list the folder: " + error.message());
  if (drive.sensors.empty()) {
    throw InputError(root.string(),
                     "holds no sensor folder (ins/, lidar/, radar/, camera/, or <kind>_<place>/)");
  }
  std::ranges::sort(drive.sensors, [](const DriveSensor& a, const DriveSensor& b) {
    return std::tie(a.kind, a.name) < std::tie(b.kind, b.name);
  });
  const fs::path truth = root / "ground_truth.yaml";
  if (fs::is_regular_file(truth, error)) drive.ground_truth = truth;
  return drive;
}

}  // namespace x2car::io
