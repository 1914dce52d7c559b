#include "x2car/io/extrinsic_merge.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/urdf_joint.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 3> kAngleNames{"roll", "pitch", "yaw"};

// A text edit: [begin, end) becomes `text` (an insertion when begin == end).
struct Edit {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::string text;
};

std::string applied(std::string_view text, std::vector<Edit> edits) {
  std::ranges::sort(edits, [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
  std::string out(text);
  for (const Edit& edit : edits) out.replace(edit.begin, edit.end - edit.begin, edit.text);
  return out;
}

std::array<std::optional<double>, 3> estimated_angles(const MergeRequest& request) {
  if (request.result == nullptr || !request.result->ok()) {
    throw std::invalid_argument(
        fmt::format("merge: '{}' has no ok result to merge", request.child_frame));
  }
  return {request.result->roll, request.result->pitch, request.result->yaw};
}

void check_parent(const std::string& parent, const std::string& vehicle_frame,
                  const std::string& child, const std::string& source, std::size_t line) {
  if (parent == vehicle_frame) return;
  throw InputError(
      source, line, child,
      fmt::format("the entry is relative to '{}', not to '{}': x2car's angles are relative to the "
                  "car body, so merging them here is right only if '{}' is aligned with it (then "
                  "name it as the vehicle frame, --parent {})",
                  parent, vehicle_frame, parent, parent));
}

std::string missing_child_message(const std::string& child, const std::vector<std::string>& all) {
  return fmt::format("no child frame '{}'; the file holds: {}", child, join(all));
}

}  // namespace

MergeOutcome merge_into_autoware(std::string_view text, const std::string& source_name,
                                 const std::string& vehicle_frame,
                                 std::span<const MergeRequest> requests) {
  const YAML::Node root = load_yaml(text, source_name);
  if (!root.IsMap() || root.size() != 1 || !root.begin()->second.IsMap()) {
    throw InputError(source_name,
                     "expected an Autoware calibration: one parent frame holding "
                     "child frames with x, y, z, roll, pitch, yaw");
  }
  const std::string parent = root.begin()->first.Scalar();
  const YAML::Node children = root.begin()->second;
  std::vector<std::string> names;
  for (const auto& entry : children) names.push_back(entry.first.Scalar());
  MergeOutcome outcome;
  std::vector<Edit> edits;
  for (const MergeRequest& request : requests) {
    const std::array<std::optional<double>, 3> estimated = estimated_angles(request);
    const YAML::Node node = children[request.child_frame];
    if (!node.IsDefined()) {
      throw InputError(source_name, yaml_line(children.Mark()), parent,
                       missing_child_message(request.child_frame, names));
    }
    check_parent(parent, vehicle_frame, request.child_frame, source_name, yaml_line(node.Mark()));
    // Checks every value as the reader does.
    parse_autoware(text, source_name, request.child_frame);
    MergedEntry entry;
    entry.child_frame = request.child_frame;
    const auto value_of = [&](const char* key) {
      const YAML::Node value = node[key];
      const FieldLocation where{source_name, yaml_line(value.Mark()),
                                request.child_frame + "." + key};
      return std::pair{value, parse_double(value.Scalar(), where)};
    };
    for (std::size_t i = 0; i < 3; ++i) {
      entry.translation[i] = value_of(std::array{"x", "y", "z"}[i]).second;
    }
    for (std::size_t i = 0; i < 3; ++i) {
      const auto [value, before] = value_of(kAngleNames[i]);
      entry.angles[i] = {kAngleNames[i], before, before, false};
      if (!estimated[i]) continue;
      // The scalar as the file spells it, at its mark: only a plain one-line number can be
      // replaced without touching what is around it.
      const auto begin = static_cast<std::size_t>(value.Mark().pos);
      const std::string& spelled = value.Scalar();
      if (text.substr(begin, spelled.size()) != spelled) {
        throw InputError(source_name, yaml_line(value.Mark()),
                         request.child_frame + "." + kAngleNames[i],
                         "cannot replace this value in place (write it as a plain number)");
      }
      entry.angles[i].after = *estimated[i];
      entry.angles[i].replaced = true;
      edits.push_back({begin, begin + spelled.size(), format_number(*estimated[i])});
    }
    outcome.entries.push_back(entry);
  }
  outcome.text = applied(text, std::move(edits));
  return outcome;
}

MergeOutcome merge_into_urdf(std::string_view text, const std::string& source_name,
                             const std::string& vehicle_frame,
                             std::span<const MergeRequest> requests) {
  const std::vector<UrdfJointOrigin> origins = urdf_joint_origins(text, source_name);
  std::vector<std::string> names;
  for (const UrdfJointOrigin& origin : origins) names.push_back(origin.child_link);
  MergeOutcome outcome;
  std::vector<Edit> edits;
  for (const MergeRequest& request : requests) {
    const std::array<std::optional<double>, 3> estimated = estimated_angles(request);
    const auto found =
        std::ranges::find(origins, request.child_frame, &UrdfJointOrigin::child_link);
    if (found == origins.end()) {
      throw InputError(source_name, missing_child_message(request.child_frame, names));
    }
    const UrdfJointOrigin& origin = *found;
    check_parent(origin.parent_link, vehicle_frame, request.child_frame, source_name, origin.line);
    const Extrinsic before = parse_urdf(text, source_name, request.child_frame);
    MergedEntry entry;
    entry.child_frame = request.child_frame;
    const Eigen::Vector3d t = before.parent_from_child.translation();
    entry.translation = {t.x(), t.y(), t.z()};
    // The rpy tokens as the file spells them; the ones estimated are replaced, the rest kept.
    std::vector<std::string> tokens = {"0", "0", "0"};
    if (origin.rpy_value) {
      const auto [begin, end] = *origin.rpy_value;
      const std::vector<std::string_view> fields = split_fields(text.substr(begin, end - begin));
      tokens.assign(fields.begin(), fields.end());
    }
    const FieldLocation where{source_name, origin.line, "origin rpy"};
    for (std::size_t i = 0; i < 3; ++i) {
      const double value = parse_double(tokens[i], where);
      entry.angles[i] = {kAngleNames[i], value, value, false};
      if (!estimated[i]) continue;
      entry.angles[i].after = *estimated[i];
      entry.angles[i].replaced = true;
      tokens[i] = format_number(*estimated[i]);
    }
    const std::string rpy = fmt::format("{} {} {}", tokens[0], tokens[1], tokens[2]);
    if (origin.rpy_value) {
      edits.push_back({origin.rpy_value->first, origin.rpy_value->second, rpy});
    } else if (origin.has_origin) {
      edits.push_back({origin.insert_at, origin.insert_at, fmt::format(" rpy=\"{}\"", rpy)});
    } else if (text.substr(origin.insert_at - 2, 2) == "/>") {
      throw InputError(source_name, origin.line, request.child_frame,
                       "the joint is an empty element: give it an <origin> to merge into");
    } else {
      edits.push_back({origin.insert_at, origin.insert_at,
                       fmt::format("\n  <origin xyz=\"0 0 0\" rpy=\"{}\"/>", rpy)});
    }
    outcome.entries.push_back(entry);
  }
  outcome.text = applied(text, std::move(edits));
  return outcome;
}

Extrinsic merge_into_extrinsic(const Extrinsic& prior, const std::string& source_name,
                               const std::string& vehicle_frame, const CalibrationResult& result,
                               MergedEntry* entry) {
  const MergeRequest request{prior.child_frame, &result};
  const std::array<std::optional<double>, 3> estimated = estimated_angles(request);
  check_parent(prior.parent_frame, vehicle_frame, prior.child_frame, source_name, 0);
  const EulerAngles before = euler_from_rotation(prior.parent_from_child.linear());
  const std::array<double, 3> before_angles{before.roll, before.pitch, before.yaw};
  MergedEntry merged;
  merged.child_frame = prior.child_frame;
  const Eigen::Vector3d t = prior.parent_from_child.translation();
  merged.translation = {t.x(), t.y(), t.z()};
  for (std::size_t i = 0; i < 3; ++i) {
    merged.angles[i] = {kAngleNames[i], before_angles[i], estimated[i].value_or(before_angles[i]),
                        estimated[i].has_value()};
  }
  if (entry != nullptr) *entry = merged;
  Extrinsic after = prior;
  after.parent_from_child = make_transform(
      EulerAngles{merged.angles[0].after, merged.angles[1].after, merged.angles[2].after}, t);
  return after;
}

std::string format_merge_table(const MergeOutcome& outcome) {
  std::string table;
  for (const MergedEntry& entry : outcome.entries) {
    table += fmt::format("{}: x y z {} {} {} m kept\n", entry.child_frame,
                         format_number(entry.translation[0]), format_number(entry.translation[1]),
                         format_number(entry.translation[2]));
    for (const MergedAngle& angle : entry.angles) {
      if (!angle.replaced) {
        table += fmt::format("  {:<6} {:>10.4f} deg  kept (not estimated)\n", angle.name,
                             deg_from_rad(angle.before));
        continue;
      }
      table += fmt::format("  {:<6} {:>10.4f} -> {:>10.4f} deg  ({:+.4f})\n", angle.name,
                           deg_from_rad(angle.before), deg_from_rad(angle.after),
                           deg_from_rad(wrap_angle(angle.after - angle.before)));
    }
  }
  return table;
}

}  // namespace x2car::io
