// The URDF form of an Extrinsic (parent_from_child, DESIGN §1): one fixed <joint> with <parent>,
// <child> and <origin xyz rpy>, rpy being R = Rz(yaw) Ry(pitch) Rx(roll) in radians as in URDF.
// A small reader for this one element, so no XML library is needed. Parsers take a source name
// and throw InputError naming it, and the line and field where they can.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "x2car/core/extrinsic.hpp"

namespace x2car::io {

// A fixed joint named "<child>_joint".
std::string format_urdf(const Extrinsic& extrinsic);

// XML comments and <transmission> blocks are ignored, a missing <origin> or attribute is zero
// (URDF's default), and when the text holds several joints `child_link` picks one (the error lists
// them otherwise).
Extrinsic parse_urdf(std::string_view text, const std::string& source_name,
                     const std::optional<std::string>& child_link = std::nullopt);

// Where a joint's rotation is written, for editing a URDF in place (extrinsic_merge.hpp): the
// offsets are into `text` as given.
struct UrdfJointOrigin {
  std::string parent_link;
  std::string child_link;
  std::size_t line = 0;  // of the <joint> tag
  // The rpy attribute's value, between its quotes: [begin, end). Absent without an rpy.
  std::optional<std::pair<std::size_t, std::size_t>> rpy_value;
  // Without an rpy: where ` rpy="..."` goes (just after "<origin"), or, without an <origin>,
  // where a whole `<origin rpy="..."/>` goes (just after the joint's start tag).
  std::size_t insert_at = 0;
  bool has_origin = false;
};

// Every joint's origin in the text (comments and <transmission> blocks passed over), in order.
std::vector<UrdfJointOrigin> urdf_joint_origins(std::string_view text, const std::string& source);

// True when the text holds a <joint> start tag: how detect_extrinsic_format recognises the form.
bool has_urdf_joint(std::string_view text);

}  // namespace x2car::io
