#include "x2car/io/ground_truth.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

constexpr std::string_view kMountingPrefix = "vehicle_from_";
constexpr std::array<const char*, 6> kMountingKeys{"x", "y", "z", "roll", "pitch", "yaw"};
constexpr std::array<const char*, 14> kTrajectoryColumns{
    "time", "x",  "y",  "z",     "roll",     "pitch",     "yaw",
    "vx",   "vy", "vz", "speed", "yaw_rate", "curvature", "straight"};

// ---- YAML reading ------------------------------------------------------------------------------

// The scalar under `key`, or an InputError naming the key.
std::string required_scalar(const YAML::Node& map, const std::string& key,
                            const std::string& source, const std::string& field) {
  const YAML::Node value = map[key];
  if (!value.IsDefined() || value.IsNull()) {
    throw InputError(source, yaml_line(value.IsDefined() ? value : map), field, "missing value");
  }
  if (!value.IsScalar()) throw InputError(source, yaml_line(value), field, "expected a scalar");
  return value.Scalar();
}

double required_number(const YAML::Node& map, const std::string& key, const std::string& source,
                       const std::string& field) {
  const std::string text = required_scalar(map, key, source, field);
  return parse_double(text, {source, yaml_line(map[key]), field});
}

std::uint64_t required_seed(const YAML::Node& map, const std::string& source) {
  const std::string text = required_scalar(map, "seed", source, "seed");
  std::uint64_t seed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
  if (error != std::errc() || end != text.data() + text.size()) {
    throw InputError(source, yaml_line(map["seed"]), "seed",
                     fmt::format("expected an unsigned 64-bit integer, found '{}'", text));
  }
  return seed;
}

SensorMounting parse_mounting(const YAML::Node& node, const std::string& key,
                              const std::string& source) {
  if (!node.IsMap()) {
    throw InputError(source, yaml_line(node), key,
                     "expected a mapping with x, y, z, roll, pitch, yaw");
  }
  std::array<double, 6> v{};
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = required_number(node, kMountingKeys[i], source, key + "." + kMountingKeys[i]);
  }
  return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
}

SensorMountings parse_mounting_entries(const YAML::Node& root, const std::string& source) {
  SensorMountings mountings;
  for (const auto& entry : root) {
    const std::string key = entry.first.Scalar();
    if (!key.starts_with(kMountingPrefix)) continue;
    const std::string sensor = key.substr(kMountingPrefix.size());
    if (sensor.empty()) {
      throw InputError(source, yaml_line(entry.first), key, "the sensor name is missing");
    }
    mountings[sensor] = parse_mounting(entry.second, key, source);
  }
  return mountings;
}

// ---- YAML writing ------------------------------------------------------------------------------

// A string as a YAML scalar that reads back as the same string (quoted only where needed).
std::string yaml_string(const std::string& value) {
  YAML::Emitter emitter;
  emitter << value;
  return emitter.c_str();
}

void check_sensor_name(const std::string& name) {
  const bool plain = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
  if (!plain) {
    throw std::invalid_argument(
        fmt::format("format_ground_truth: sensor name '{}' is not [A-Za-z0-9_]+", name));
  }
}

std::string mounting_entry(const std::string& sensor, const SensorMounting& m) {
  check_sensor_name(sensor);
  return fmt::format("{}{}:\n  x: {}\n  y: {}\n  z: {}\n  roll: {}\n  pitch: {}\n  yaw: {}\n",
                     kMountingPrefix, sensor, format_number(m.translation.x()),
                     format_number(m.translation.y()), format_number(m.translation.z()),
                     format_number(m.rotation.roll), format_number(m.rotation.pitch),
                     format_number(m.rotation.yaw));
}

// ---- trajectory CSV ----------------------------------------------------------------------------

std::string trajectory_line(const TrajectoryRow& row) {
  const Eigen::Vector3d p = row.world_from_vehicle.translation();
  const EulerAngles a = euler_from_rotation(row.world_from_vehicle.linear());
  const Eigen::Vector3d& v = row.velocity_enu;
  return format_numbers({row.time, p.x(), p.y(), p.z(), a.roll, a.pitch, a.yaw, v.x(), v.y(), v.z(),
                         row.speed, row.yaw_rate, row.curvature},
                        ",") +
         (row.straight ? ",1\n" : ",0\n");
}

TrajectoryRow trajectory_row(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> fields = split_fields(line.text);
  const std::vector<double> v =
      parse_named_doubles(fields, kTrajectoryColumns, source, line.number);
  if (v[13] != 0.0 && v[13] != 1.0) {
    throw InputError(source, line.number, "straight",
                     fmt::format("expected 0 or 1, found '{}'", fields[13]));
  }
  TrajectoryRow row;
  row.time = v[0];
  row.world_from_vehicle = make_transform(EulerAngles{v[4], v[5], v[6]}, {v[1], v[2], v[3]});
  row.velocity_enu = {v[7], v[8], v[9]};
  row.speed = v[10];
  row.yaw_rate = v[11];
  row.curvature = v[12];
  row.straight = v[13] == 1.0;
  return row;
}

}  // namespace

Eigen::Isometry3d SensorMounting::vehicle_from_sensor() const {
  return make_transform(rotation, translation);
}

SensorMounting mounting_from_transform(const Eigen::Isometry3d& vehicle_from_sensor) {
  return {vehicle_from_sensor.translation(), euler_from_rotation(vehicle_from_sensor.linear())};
}

std::string format_ground_truth(const GroundTruth& truth) {
  std::string text =
      "# x2car simulator ground truth. vehicle_from_<sensor>: p_V = R_V_S p_S + t_V_S with\n"
      "# t_V_S = (x, y, z) [m] and R_V_S = Rz(yaw) Ry(pitch) Rx(roll) [rad] "
      "(docs/conventions.md).\n";
  text += fmt::format("scenario: {}\nseed: {}\nduration_s: {}\ntrajectory: {}\n",
                      yaml_string(truth.scenario), truth.seed, format_number(truth.duration_s),
                      yaml_string(truth.trajectory_file));
  for (const auto& [sensor, mounting] : truth.vehicle_from_sensor) {
    text += mounting_entry(sensor, mounting);
  }
  return text;
}

void write_ground_truth(const std::filesystem::path& path, const GroundTruth& truth) {
  write_text_file(path, format_ground_truth(truth));
}

GroundTruth read_ground_truth(const std::filesystem::path& path) {
  return parse_ground_truth(read_text_file(path), path.string());
}

GroundTruth parse_ground_truth(std::string_view text, const std::string& source_name) {
  const YAML::Node root = load_yaml_mapping(text, source_name);
  GroundTruth truth;
  truth.scenario = required_scalar(root, "scenario", source_name, "scenario");
  truth.seed = required_seed(root, source_name);
  truth.duration_s = required_number(root, "duration_s", source_name, "duration_s");
  truth.trajectory_file = required_scalar(root, "trajectory", source_name, "trajectory");
  truth.vehicle_from_sensor = parse_mounting_entries(root, source_name);
  return truth;
}

SensorMountings read_mountings(const std::filesystem::path& path) {
  return parse_mountings(read_text_file(path), path.string());
}

SensorMountings parse_mountings(std::string_view text, const std::string& source_name) {
  SensorMountings mountings =
      parse_mounting_entries(load_yaml_mapping(text, source_name), source_name);
  if (mountings.empty()) {
    throw InputError(source_name, "no vehicle_from_<sensor> mapping (x y z roll pitch yaw)");
  }
  return mountings;
}

std::string format_trajectory_csv(std::span<const TrajectoryRow> rows) {
  // Appended, not `std::string(header) + "\n"`: GCC 12 -O2 reports a false -Warray-bounds there.
  std::string text(kTrajectoryCsvHeader);
  text += '\n';
  for (const TrajectoryRow& row : rows) text += trajectory_line(row);
  return text;
}

void write_trajectory_csv(const std::filesystem::path& path, std::span<const TrajectoryRow> rows) {
  write_text_file(path, format_trajectory_csv(rows));
}

std::vector<TrajectoryRow> read_trajectory_csv(const std::filesystem::path& path) {
  return parse_trajectory_csv(read_text_file(path), path.string());
}

std::vector<TrajectoryRow> parse_trajectory_csv(std::string_view text,
                                                const std::string& source_name) {
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty() || trim(lines.front().text) != kTrajectoryCsvHeader) {
    throw InputError(source_name, lines.empty() ? 0 : lines.front().number, {},
                     fmt::format("expected the header '{}'", kTrajectoryCsvHeader));
  }
  std::vector<TrajectoryRow> rows;
  std::vector<double> times;
  std::vector<std::size_t> numbers;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    rows.push_back(trajectory_row(lines[i], source_name));
    times.push_back(rows.back().time);
    numbers.push_back(lines[i].number);
  }
  check_increasing_times(times, numbers, source_name, "time");
  return rows;
}

std::optional<SensorMounting> find_mounting(const GroundTruth& truth, const std::string& sensor) {
  const auto found = truth.vehicle_from_sensor.find(sensor);
  if (found == truth.vehicle_from_sensor.end()) return std::nullopt;
  return found->second;
}

}  // namespace x2car::io
