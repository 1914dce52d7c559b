#include "x2car/io/autoware_yaml.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 6> kAutowareKeys{"x", "y", "z", "roll", "pitch", "yaw"};

std::vector<std::string> yaml_keys(const YAML::Node& map) {
  std::vector<std::string> keys;
  for (const auto& entry : map) keys.push_back(entry.first.Scalar());
  return keys;
}

bool is_autoware_leaf(const YAML::Node& node) {
  if (!node.IsMap()) return false;
  return std::all_of(kAutowareKeys.begin(), kAutowareKeys.end(),
                     [&node](const char* key) { return node[key].IsDefined(); });
}

struct AutowareFile {
  std::string parent;
  YAML::Node children;
};

AutowareFile autoware_file(std::string_view text, const std::string& source) {
  const YAML::Node root = load_yaml(text, source);
  if (!root.IsMap() || root.size() != 1) {
    throw InputError(source, yaml_line(root.Mark()), {},
                     fmt::format("expected one parent frame at the top level "
                                 "(parent: child: x/y/z/roll/pitch/yaw), found {}",
                                 root.IsMap() ? join(yaml_keys(root)) : "none"));
  }
  const auto entry = *root.begin();
  if (!entry.second.IsMap() || entry.second.size() == 0) {
    throw InputError(source, yaml_line(entry.second.Mark()), entry.first.Scalar(),
                     "the parent frame holds no child frames");
  }
  return {entry.first.Scalar(), entry.second};
}

Extrinsic autoware_child(const std::string& parent, const std::string& child,
                         const YAML::Node& node, const std::string& source) {
  if (!node.IsMap()) {
    throw InputError(source, yaml_line(node.Mark()), child,
                     "expected a mapping with x, y, z, roll, pitch, yaw");
  }
  std::array<double, 6> v{};
  for (std::size_t i = 0; i < kAutowareKeys.size(); ++i) {
    const YAML::Node value = node[kAutowareKeys[i]];
    const FieldLocation where{source, yaml_line(value.IsDefined() ? value.Mark() : node.Mark()),
                              child + "." + kAutowareKeys[i]};
    if (!value.IsDefined() || value.IsNull()) {
      throw InputError(where.file, where.line, where.field, "missing value");
    }
    if (!value.IsScalar()) throw InputError(where.file, where.line, where.field, "not a number");
    v[i] = parse_double(value.Scalar(), where);
    check_plausible(v[i], i < 3 ? kExtrinsicMaxValue : kExtrinsicMaxRadians, value.Scalar(),
                    i < 3 ? "m" : "rad", where, i < 3 ? "" : "Autoware angles are radians");
  }
  Extrinsic extrinsic{parent, child,
                      make_transform(EulerAngles{v[3], v[4], v[5]}, {v[0], v[1], v[2]})};
  return extrinsic;
}

// Quotes a frame name that YAML would not read back as the same plain string.
std::string yaml_key(const std::string& name) {
  const bool is_null_word = name == "null" || name == "Null" || name == "NULL";
  const bool plain = !name.empty() && !is_null_word && name.front() != '-' &&
                     std::all_of(name.begin(), name.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) != 0 ||
                              std::string_view("_/.-").find(c) != std::string_view::npos;
                     });
  if (plain) return name;
  std::string quoted = "\"";
  for (const char c : name) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

std::string autoware_entry(const Extrinsic& extrinsic) {
  const Eigen::Vector3d t = extrinsic.parent_from_child.translation();
  const EulerAngles a = euler_from_rotation(extrinsic.parent_from_child.linear());
  return fmt::format(
      "  {}:\n    x: {}\n    y: {}\n    z: {}\n    roll: {}\n    pitch: {}\n"
      "    yaw: {}\n",
      yaml_key(extrinsic.child_frame), format_number(t.x()), format_number(t.y()),
      format_number(t.z()), format_number(a.roll), format_number(a.pitch), format_number(a.yaw));
}

}  // namespace

std::string format_autoware(const Extrinsic& extrinsic) {
  return format_autoware(std::span<const Extrinsic>(&extrinsic, 1));
}

std::string format_autoware(std::span<const Extrinsic> extrinsics) {
  if (extrinsics.empty()) throw std::invalid_argument("format_autoware: no extrinsics");
  const std::string& parent = extrinsics.front().parent_frame;
  std::string text = yaml_key(parent) + ":\n";
  std::vector<std::string> children;
  for (const Extrinsic& extrinsic : extrinsics) {
    if (extrinsic.parent_frame != parent) {
      throw std::invalid_argument(fmt::format("format_autoware: parent frames differ ('{}', '{}')",
                                              parent, extrinsic.parent_frame));
    }
    if (std::find(children.begin(), children.end(), extrinsic.child_frame) != children.end()) {
      throw std::invalid_argument(
          fmt::format("format_autoware: child frame '{}' appears twice", extrinsic.child_frame));
    }
    children.push_back(extrinsic.child_frame);
    text += autoware_entry(extrinsic);
  }
  return text;
}

Extrinsic parse_autoware(std::string_view text, const std::string& source_name,
                         const std::optional<std::string>& child_frame) {
  const AutowareFile file = autoware_file(text, source_name);
  const std::vector<std::string> children = yaml_keys(file.children);
  if (child_frame) {
    const YAML::Node node = file.children[*child_frame];
    if (!node.IsDefined()) {
      throw InputError(source_name, fmt::format("no child frame '{}' under '{}'; present: {}",
                                                *child_frame, file.parent, join(children)));
    }
    return autoware_child(file.parent, *child_frame, node, source_name);
  }
  if (children.size() != 1) {
    throw InputError(source_name,
                     fmt::format("'{}' holds {} child frames ({}); name the one to read",
                                 file.parent, children.size(), join(children)));
  }
  // The node itself, not a lookup by its name: a key whose text does not find it again (a null
  // key reads as "") gave an invalid node, and yaml-cpp threw (fuzz finding).
  return autoware_child(file.parent, children.front(), file.children.begin()->second, source_name);
}

std::vector<Extrinsic> parse_autoware_all(std::string_view text, const std::string& source_name) {
  const AutowareFile file = autoware_file(text, source_name);
  std::vector<Extrinsic> extrinsics;
  for (const auto& child : file.children) {
    extrinsics.push_back(
        autoware_child(file.parent, child.first.Scalar(), child.second, source_name));
  }
  return extrinsics;
}

bool looks_like_autoware(std::string_view text) {
  if (text.find(':') == text.npos) return false;
  try {
    const YAML::Node root = YAML::Load(std::string(text));
    if (!root.IsMap()) return false;
    for (const auto& parent : root) {
      if (!parent.second.IsMap()) continue;
      for (const auto& child : parent.second) {
        if (is_autoware_leaf(child.second)) return true;
      }
    }
  } catch (const YAML::Exception&) {
  }
  return false;
}

}  // namespace x2car::io
