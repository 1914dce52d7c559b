// The URDF form of an Extrinsic (parent_from_child, DESIGN §1): one fixed <joint> with <parent>,
// <child> and <origin xyz rpy>, rpy being R = Rz(yaw) Ry(pitch) Rx(roll) in radians as in URDF.
// A small reader for this one element, so no XML library is needed. Parsers take a source name
// and throw InputError naming it, and the line and field where they can.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "x2car/core/extrinsic.hpp"

namespace x2car::io {

// A fixed joint named "<child>_joint".
std::string format_urdf(const Extrinsic& extrinsic);

// XML comments and <transmission> blocks are ignored, a missing <origin> or attribute is zero
// (URDF's default), and when the text holds several joints `child_link` picks one (the error lists
// them otherwise).
Extrinsic parse_urdf(std::string_view text, const std::string& source_name,
                     const std::optional<std::string>& child_link = std::nullopt);

// True when the text holds a <joint> start tag: how detect_extrinsic_format recognises the form.
bool has_urdf_joint(std::string_view text);

}  // namespace x2car::io
