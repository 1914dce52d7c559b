#include "x2car/io/drive_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <system_error>

#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_ins.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

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
  if (fs::is_regular_file(root / kDriveManifestName, error)) {
    return read_drive_manifest(root / kDriveManifestName);
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
      drive.sensors.push_back({name, *kind, log, {}, {}, {}, {}});
    } else {
      drive.sensors.push_back({name, *kind, entry.path(), {}, {}, {}, {}});
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

namespace {

// The keys a sensor of each type may have besides `type` and `input`.
bool key_fits(SensorKind kind, const std::string& key) {
  if (key == "type" || key == "input" || key == "topic") return true;
  if (key == "intrinsics") return kind == SensorKind::kCamera;
  if (key == "lever_arm" || key == "nominal_yaw_deg") return kind == SensorKind::kRadar;
  return false;
}

double number_at(const YAML::Node& node, const std::string& source, const std::string& key) {
  try {
    const double value = node.as<double>();
    if (std::isfinite(value)) return value;
  } catch (const YAML::Exception&) {
  }
  throw InputError(source, yaml_line(node), key, "expected a finite number");
}

DriveFolder read_drive_manifest_checked(const fs::path& manifest) {
  const std::string source = manifest.string();
  const YAML::Node root = load_yaml_mapping(read_text_file(manifest), source);
  const fs::path base = manifest.parent_path();
  const auto existing = [&](const YAML::Node& node, const std::string& key) {
    if (!node.IsScalar()) throw InputError(source, yaml_line(node), key, "expected a path");
    const fs::path path = base / node.as<std::string>();
    std::error_code error;
    if (!fs::exists(path, error)) {
      throw InputError(source, yaml_line(node), key,
                       fmt::format("{} does not exist", path.string()));
    }
    return path;
  };
  DriveFolder drive;
  drive.root = base;
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key != "sensors" && key != "ground_truth") {
      throw InputError(source, yaml_line(entry.first), key,
                       "unknown key (the manifest has `sensors` and `ground_truth`)");
    }
  }
  const YAML::Node sensors = root["sensors"];
  if (!sensors || !sensors.IsMap() || sensors.size() == 0) {
    throw InputError(source, sensors ? yaml_line(sensors) : 0, "sensors",
                     "expected a mapping of sensor names to {type, input, ...}");
  }
  std::vector<std::string> ins_names;
  for (const auto& entry : sensors) {
    const std::string name = entry.first.as<std::string>();
    const std::string prefix = "sensors." + name;
    const YAML::Node& fields = entry.second;
    if (name.empty() || !std::ranges::all_of(name, [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
        })) {
      throw InputError(source, yaml_line(entry.first), prefix,
                       "a sensor's name is its frame's: letters, digits and _ only");
    }
    if (!fields.IsMap()) {
      throw InputError(source, yaml_line(fields), prefix, "expected {type, input, ...}");
    }
    const YAML::Node type = fields["type"];
    if (!type || !type.IsScalar()) {
      throw InputError(source, yaml_line(fields), prefix + ".type",
                       "missing: one of ins, lidar, radar, camera");
    }
    SensorKind kind_value = SensorKind::kIns;
    try {
      kind_value = enum_from_string(kSensorKindNames, type.as<std::string>(), "type");
    } catch (const std::invalid_argument& error) {
      throw InputError(source, yaml_line(type), prefix + ".type", error.what());
    }
    const std::optional<SensorKind> kind = kind_value;
    for (const auto& field : fields) {
      const std::string field_name = field.first.as<std::string>();
      if (!key_fits(*kind, field_name)) {
        throw InputError(source, yaml_line(field.first), prefix + "." + field_name,
                         fmt::format("not a key of a sensor of type {}", to_string(*kind)));
      }
    }
    const YAML::Node input = fields["input"];
    if (!input) throw InputError(source, yaml_line(fields), prefix + ".input", "missing");
    DriveSensor sensor{name, *kind, existing(input, prefix + ".input"), {}, {}, {}, {}};
    if (const YAML::Node topic = fields["topic"]) {
      if (!topic.IsScalar())
        throw InputError(source, yaml_line(topic), prefix + ".topic", "a name");
      sensor.topic = topic.as<std::string>();
    }
    if (const YAML::Node intrinsics = fields["intrinsics"]) {
      sensor.intrinsics = existing(intrinsics, prefix + ".intrinsics");
    }
    if (const YAML::Node lever = fields["lever_arm"]) {
      if (!lever.IsSequence() || lever.size() != 2) {
        throw InputError(source, yaml_line(lever), prefix + ".lever_arm", "expected [x, y] in m");
      }
      sensor.lever_arm_m =
          std::array<double, 2>{number_at(lever[0], source, prefix + ".lever_arm"),
                                number_at(lever[1], source, prefix + ".lever_arm")};
    }
    if (const YAML::Node yaw = fields["nominal_yaw_deg"]) {
      sensor.nominal_yaw_deg = number_at(yaw, source, prefix + ".nominal_yaw_deg");
    }
    if (*kind == SensorKind::kIns) {
      ins_names.push_back(name);
      drive.ins_log = sensor.input;
      drive.ins_topic = sensor.topic;
    }
    drive.sensors.push_back(std::move(sensor));
  }
  if (ins_names.size() > 1) {
    throw InputError(source, yaml_line(sensors), "sensors",
                     fmt::format("two GNSS/INS sensors ({}): the radars and cameras take the car's "
                                 "motion from one; describe one",
                                 join(ins_names)));
  }
  if (const YAML::Node truth = root["ground_truth"]) {
    drive.ground_truth = existing(truth, "ground_truth");
  }
  std::ranges::stable_sort(
      drive.sensors, [](const DriveSensor& a, const DriveSensor& b) { return a.kind < b.kind; });
  return drive;
}

}  // namespace

DriveFolder read_drive_manifest(const fs::path& manifest) {
  // A shape yaml-cpp cannot convert (a key that is a list, a null key) is the file's error, not
  // x2car's: InputError, never an escaped YAML::Exception.
  try {
    return read_drive_manifest_checked(manifest);
  } catch (const YAML::Exception& error) {
    throw InputError(manifest.string(), yaml_line(error.mark), "",
                     std::string("not a manifest x2car reads: ") + error.msg);
  }
}

namespace {

// The kind of sensor a topic's type feeds, when it is one; the GNSS/INS topics apart.
std::optional<SensorKind> sensor_kind_of(const std::string& type) {
  if (ros_type_is(type, "sensor_msgs/PointCloud2")) return SensorKind::kLidar;
  if (ros_type_is(type, "radar_msgs/RadarScan") || ros_type_is(type, "radar_msgs/RadarTracks")) {
    return SensorKind::kRadar;
  }
  if (ros_type_is(type, "sensor_msgs/Image") || ros_type_is(type, "sensor_msgs/CompressedImage")) {
    return SensorKind::kCamera;
  }
  return std::nullopt;
}

// A frame or topic name as a sensor's name (letters, digits, _): "/sensing/lidar/top/points" ->
// "sensing_lidar_top_points".
std::string sensor_name_of(const std::string& text) {
  std::string name;
  for (const char c : text) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) != 0;
    if (plain || !name.empty()) name += plain ? c : '_';
  }
  while (name.ends_with('_')) name.pop_back();
  return name;
}

}  // namespace

DriveFolder find_bag_sensors(const fs::path& path) {
  const std::unique_ptr<BagFile> bag = open_bag(path);
  // Each sensor topic's frame (its first message's header.frame_id; Odometry's child_frame_id, the
  // device's): the child frame its results are written for, as ROS and Autoware name it.
  const auto wanted = [](const BagTopic& topic) {
    return sensor_kind_of(topic.type).has_value() || is_ins_pose_type(topic.type) ||
           ros_type_is(topic.type, "sensor_msgs/NavSatFix");
  };
  std::map<std::size_t, std::string> frames;
  bag->scan(wanted, [&](const BagMessage& message) {
    const BagTopic& topic = bag->topics()[message.topic];
    if (!wanted(topic) || frames.contains(message.topic)) return;
    try {
      RosMessageReader reader(message.data, ros_encoding_of(topic, path), path.string());
      std::string frame = reader.header().frame_id;
      if (ros_type_is(topic.type, "nav_msgs/Odometry")) frame = reader.string("child_frame_id");
      if (ros_type_is(topic.type, "geometry_msgs/PoseStamped")) frame.clear();  // the world's
      frames[message.topic] = frame;
    } catch (const InputError&) {
      frames[message.topic] = "";  // named by its topic; its own reader reports the error
    }
  });
  DriveFolder drive;
  drive.root = path;
  std::set<std::string> taken;
  // The frame's name, a camera's optical frame as its body's; the topic's when there is no frame
  // or another sensor has it.
  const auto name_of = [&](std::size_t index, SensorKind kind) {
    std::string frame = frames.contains(index) ? sensor_name_of(frames.at(index)) : "";
    if (kind == SensorKind::kCamera) {
      for (const std::string_view suffix : {"_optical_frame", "_optical"}) {
        if (frame.ends_with(suffix)) frame = frame.substr(0, frame.size() - suffix.size());
      }
    }
    std::string name = !frame.empty() && !taken.contains(frame)
                           ? frame
                           : sensor_name_of(bag->topics()[index].name);
    if (name.empty() || taken.contains(name)) name = fmt::format("sensor_{}", index);
    taken.insert(name);
    return name;
  };
  std::vector<std::size_t> pose_topics;
  std::vector<std::size_t> fix_topics;
  for (std::size_t i = 0; i < bag->topics().size(); ++i) {
    const std::string& type = bag->topics()[i].type;
    if (is_ins_pose_type(type)) {
      pose_topics.push_back(i);
    } else if (ros_type_is(type, "sensor_msgs/NavSatFix")) {
      fix_topics.push_back(i);
    } else if (const std::optional<SensorKind> kind = sensor_kind_of(type)) {
      drive.sensors.push_back(
          DriveSensor{name_of(i, *kind), *kind, path, {}, {}, {}, bag->topics()[i].name});
    }
  }
  if (pose_topics.size() > 1) {
    std::vector<std::string> names;
    for (const std::size_t i : pose_topics) names.push_back(bag->topics()[i].name);
    throw InputError(path.string(),
                     fmt::format("holds {} pose topics ({}): calibrate the GNSS/INS with "
                                 "`calibrate ins --topic`, or name each sensor's topic in an "
                                 "x2car.yaml manifest",
                                 names.size(), join(names)));
  }
  const std::vector<std::size_t>& ins = pose_topics.empty() ? fix_topics : pose_topics;
  if (ins.size() == 1) {
    const std::string& topic = bag->topics()[ins.front()].name;
    drive.ins_log = path;
    drive.ins_topic = topic;
    drive.sensors.insert(
        drive.sensors.begin(),
        DriveSensor{
            name_of(ins.front(), SensorKind::kIns), SensorKind::kIns, path, {}, {}, {}, topic});
  }
  if (drive.sensors.empty()) {
    throw InputError(path.string(), "holds no topic a calibrator reads (x2car inspect lists them)");
  }
  std::ranges::stable_sort(
      drive.sensors, [](const DriveSensor& a, const DriveSensor& b) { return a.kind < b.kind; });
  return drive;
}

}  // namespace x2car::io
