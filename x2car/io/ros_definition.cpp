#include "x2car/io/ros_definition.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <set>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// "package/msg/Type" as "package/Type".
std::string plain_type(std::string_view type) {
  std::string plain(type);
  if (const auto at = plain.find("/msg/"); at != std::string::npos) plain.erase(at, 4);
  return plain;
}

bool is_primitive(std::string_view type) {
  static const std::set<std::string_view> kPrimitives = {
      "bool",   "byte",  "char",   "int8",    "uint8",   "int16",  "uint16", "int32",
      "uint32", "int64", "uint64", "float32", "float64", "string", "time",   "duration"};
  return kPrimitives.contains(type);
}

}  // namespace

RosDefinition::RosDefinition(std::string_view root_type, std::string_view text,
                             const std::string& source)
    : root_(plain_type(root_type)) {
  std::string current = root_;
  types_[current];
  for (const TextLine& line : split_lines(text)) {
    std::string_view content = line.text;
    if (const auto hash = content.find('#'); hash != std::string_view::npos) {
      content = content.substr(0, hash);
    }
    content = trim(content);
    if (content.empty() || content.starts_with("===")) continue;
    if (content.starts_with("MSG:")) {
      current = plain_type(trim(content.substr(4)));
      types_[current];
      continue;
    }
    const auto space = content.find_first_of(" \t");
    if (space == std::string_view::npos) {
      throw InputError(source, line.number, {},
                       fmt::format("'{}' in the message definition is not a field", content));
    }
    std::string_view type = content.substr(0, space);
    const std::string_view rest = trim(content.substr(space));
    // A constant ("uint8 GOOD=3", "uint8 GOOD = 3"): no bytes in the message.
    const auto name_end = rest.find_first_of(" \t=");
    if (rest.find('=') != std::string_view::npos && trim(rest.substr(name_end)).starts_with('=')) {
      continue;
    }
    Field field;
    field.name = std::string(rest.substr(0, name_end));  // a ROS 2 default value follows, if any
    if (const auto bracket = type.find('['); bracket != std::string_view::npos) {
      field.is_array = true;
      const std::string_view length = type.substr(bracket + 1, type.size() - bracket - 2);
      if (!length.empty() && !length.starts_with("<=")) {
        int count = 0;
        const auto parsed = std::from_chars(length.data(), length.data() + length.size(), count);
        if (parsed.ec != std::errc() || count < 0) {
          throw InputError(source, line.number, field.name,
                           fmt::format("array length '{}' is not a number", length));
        }
        field.fixed_length = count;
      }
      type = type.substr(0, bracket);
    }
    if (const auto bound = type.find("<="); bound != std::string_view::npos) {
      type = type.substr(0, bound);  // a bounded string reads as a string
    }
    if (is_primitive(type)) {
      field.type = std::string(type);
    } else if (type == "Header") {
      field.type = "std_msgs/Header";
    } else if (type.find('/') == std::string_view::npos) {
      field.type = current.substr(0, current.find('/') + 1) + std::string(type);
    } else {
      field.type = plain_type(type);
    }
    types_[current].push_back(std::move(field));
  }
  for (const auto& [name, fields] : types_) {
    for (const Field& field : fields) {
      if (!is_primitive(field.type) && !types_.contains(field.type)) {
        throw InputError(source, 0, name + "." + field.name,
                         fmt::format("the message definition does not define {}", field.type));
      }
    }
  }
}

void RosDefinition::walk(const std::string& type, const std::string& prefix,
                         RosMessageReader& message, const std::vector<std::string>& paths,
                         std::map<std::string, double>& out, int depth) const {
  // A type that holds itself (only a malformed definition does) would recurse without reading.
  constexpr int kMaxDepth = 32;
  if (depth > kMaxDepth) {
    throw InputError(message.source(), 0, prefix,
                     fmt::format("types nest more than {} deep in the definition", kMaxDepth));
  }
  for (const Field& field : types_.at(type)) {
    const std::string path = prefix + field.name;
    const std::size_t count =
        field.is_array ? (field.fixed_length >= 0 ? static_cast<std::size_t>(field.fixed_length)
                                                  : message.uint32(path.c_str()))
                       : 1;
    if (field.is_array && field.type == "uint8" && field.fixed_length < 0) {
      message.fixed_bytes(count, path.c_str());
      continue;
    }
    for (std::size_t i = 0; i < count; ++i) {
      const std::string at = field.is_array ? fmt::format("{}[{}]", path, i) : path;
      const char* name = at.c_str();
      if (!is_primitive(field.type)) {
        walk(field.type, at + ".", message, paths, out, depth + 1);
        continue;
      }
      double value = 0.0;
      const std::string& t = field.type;
      if (t == "string") {
        message.string(name);
        continue;
      }
      if (t == "time" || t == "duration") {  // ROS 1: two 32-bit integers
        const double sec = t == "time" ? static_cast<double>(message.uint32(name))
                                       : static_cast<double>(message.int32(name));
        const double nsec = static_cast<double>(message.uint32(name));
        for (const auto& [suffix, part] : {std::pair{".sec", sec}, std::pair{".nsec", nsec}}) {
          if (std::ranges::find(paths, at + suffix) != paths.end()) out[at + suffix] = part;
        }
        continue;
      }
      if (t == "bool" || t == "uint8" || t == "char" || t == "byte") {
        value = message.uint8(name);
      } else if (t == "int8") {
        value = static_cast<std::int8_t>(message.uint8(name));
      } else if (t == "uint16") {
        value = message.uint16(name);
      } else if (t == "int16") {
        value = std::bit_cast<std::int16_t>(message.uint16(name));
      } else if (t == "uint32") {
        value = message.uint32(name);
      } else if (t == "int32") {
        value = message.int32(name);
      } else if (t == "uint64") {
        value = static_cast<double>(message.uint64(name));
      } else if (t == "int64") {
        value = static_cast<double>(std::bit_cast<std::int64_t>(message.uint64(name)));
      } else if (t == "float32") {
        value = message.float32(name);
      } else {
        value = message.float64(name);
      }
      if (std::ranges::find(paths, at) != paths.end()) out[at] = value;
    }
  }
}

std::map<std::string, double> RosDefinition::read_numbers(
    std::string_view bytes, RosEncoding encoding, const std::string& source,
    const std::vector<std::string>& paths) const {
  RosMessageReader message(bytes, encoding, source);
  std::map<std::string, double> out;
  walk(root_, "", message, paths, out, 0);
  return out;
}

}  // namespace x2car::io
