// Results merged into a file the user's stack already reads (issue 16 item 5): an Autoware
// sensor_kit_calibration.yaml or a URDF. Only the angles a result estimated change; every other
// byte of the file stays as it was, so translations, unobservable angles (a radar's roll and
// pitch, a GNSS/INS's roll), other sensors, comments and layout survive bit for bit. Writing a
// result on its own (format_autoware, format_urdf) would instead write 0 for all it did not
// estimate and erase measured lever arms.
//
// The file's entry is parent_from_child with R = Rz(yaw) Ry(pitch) Rx(roll), as both forms and
// x2car have it (docs/conventions.md); replacing some of the three angles and keeping the others is
// the mounting with those angles changed. The entry's parent must be the frame x2car's angles are
// relative to, the car body (`vehicle_frame`, base_link by default): an entry under a sensor kit's
// own frame would get the car's angles in the kit's frame, which is wrong unless the two are
// aligned; the user says so by naming the kit frame as the vehicle frame.
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/extrinsic.hpp"

namespace x2car::io {

// One sensor's result and the child frame its entry has in the file (e.g. "lidar" ->
// "velodyne_top_base_link"). A camera's entry must be its body frame (camera_link: x forward),
// not the optical frame.
struct MergeRequest {
  std::string child_frame;
  const CalibrationResult* result = nullptr;  // status ok
};

// One angle of one entry, before and after.
struct MergedAngle {
  const char* name = "";  // "roll", "pitch", "yaw"
  double before = 0.0;    // [rad], as the file had it
  double after = 0.0;     // [rad]
  bool replaced = false;  // the result estimated it
};

struct MergedEntry {
  std::string child_frame;
  std::array<double, 3> translation{};  // x y z as the file has them (kept) [m]
  std::array<MergedAngle, 3> angles;
};

struct MergeOutcome {
  std::string text;  // the file with the estimated angles replaced
  std::vector<MergedEntry> entries;
};

// Throws InputError naming `source_name` (and the line and field where known) when the text is
// not the form, a child frame is not in it (listing those that are), its parent is not
// `vehicle_frame`, or a value cannot be edited in place (a quoted or multi-line YAML scalar);
// std::invalid_argument for a request without an ok result.
MergeOutcome merge_into_autoware(std::string_view text, const std::string& source_name,
                                 const std::string& vehicle_frame,
                                 std::span<const MergeRequest> requests);
MergeOutcome merge_into_urdf(std::string_view text, const std::string& source_name,
                             const std::string& vehicle_frame,
                             std::span<const MergeRequest> requests);

// The same on an extrinsic already read (a --prior in any form): `prior` with the angles the result
// estimated replaced, its translation and other angles kept (numerically: the form's own text is
// not kept). The entry reports the prior's angles as its Euler angles. InputError naming
// `source_name` when the prior's parent is not `vehicle_frame`; std::invalid_argument for a
// result that is not ok.
Extrinsic merge_into_extrinsic(const Extrinsic& prior, const std::string& source_name,
                               const std::string& vehicle_frame, const CalibrationResult& result,
                               MergedEntry* entry = nullptr);

// "before -> after" lines for a person: each entry's angles [deg] with the change, kept ones
// marked as kept, and its translation (always kept).
std::string format_merge_table(const MergeOutcome& outcome);

}  // namespace x2car::io
