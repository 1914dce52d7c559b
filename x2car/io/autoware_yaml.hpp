// The Autoware form of an Extrinsic (parent_from_child, DESIGN §1): sensor_kit_calibration.yaml,
//   parent:
//     child: {x, y, z, roll, pitch, yaw}
// in metres and radians, R = Rz(yaw) Ry(pitch) Rx(roll). Parsers take a source name and throw
// InputError naming it, and the line and field where they can.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/extrinsic.hpp"

namespace x2car::io {

std::string format_autoware(const Extrinsic& extrinsic);
// All extrinsics must share one parent frame and have distinct children (std::invalid_argument).
std::string format_autoware(std::span<const Extrinsic> extrinsics);

// Several children may share the parent; `child_frame` picks one (the error lists the children
// present when it is needed and missing, or names an absent one).
Extrinsic parse_autoware(std::string_view text, const std::string& source_name,
                         const std::optional<std::string>& child_frame = std::nullopt);
std::vector<Extrinsic> parse_autoware_all(std::string_view text, const std::string& source_name);

// True when the text is a YAML mapping with a leaf holding x/y/z/roll/pitch/yaw under a parent:
// how detect_extrinsic_format recognises the form.
bool looks_like_autoware(std::string_view text);

}  // namespace x2car::io
