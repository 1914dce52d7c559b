// Every textual form users meet for an Extrinsic (parent_from_child, DESIGN §1), each both ways.
// Writers print numbers with the shortest text that reads back to the same double; parsers take a
// source name (file name or "--extrinsic") and throw InputError naming it, and the line and field
// where they can, on malformed input. Formats without frame names leave Extrinsic's defaults.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/extrinsic.hpp"
#include "x2car/io/angle_unit.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/urdf_joint.hpp"

namespace x2car::io {

enum class ExtrinsicFormat {
  kXyzRpyDeg,   // "x y z roll pitch yaw", metres and degrees
  kXyzRpyRad,   // "x y z roll pitch yaw", metres and radians
  kMatrix,      // 4x4 homogeneous matrix, 16 numbers row-major
  kQuaternion,  // "x y z qx qy qz qw" (TUM order)
  kUrdf,        // <joint type="fixed"> with <parent>, <child>, <origin xyz rpy>
  kAutoware,    // sensor_kit_calibration.yaml: parent: child: {x, y, z, roll, pitch, yaw}
  kReference,   // the reference implementation's "Extrinsic:" + [r00,r01,r02,t0],...,[0,0,0,1]
};

// Names: xyzrpy-deg, xyzrpy-rad, matrix, quaternion, urdf, autoware, reference.
const char* to_string(ExtrinsicFormat format);
// Throws std::invalid_argument listing the valid names when `name` is none of them.
ExtrinsicFormat extrinsic_format_from_string(std::string_view name);
std::vector<std::string> extrinsic_format_names();

std::string format_extrinsic(const Extrinsic& extrinsic, ExtrinsicFormat format);
Extrinsic parse_extrinsic(std::string_view text, ExtrinsicFormat format,
                          const std::string& source_name);

// Recognises a form by its shape: XML <joint> -> urdf; a line "Extrinsic:" -> reference; a YAML
// mapping whose leaves hold x/y/z/roll/pitch/yaw -> autoware; 16 numbers -> matrix; 7 ->
// quaternion. Six numbers give nullopt: degrees and radians look alike, so the caller must ask.
std::optional<ExtrinsicFormat> detect_extrinsic_format(std::string_view text);

// ---- the single forms -----------------------------------------------------------------------
// Text forms allow blank lines and '#' comment lines around the numbers.

// R = Rz(yaw) Ry(pitch) Rx(roll) (DESIGN §1).
std::string format_xyzrpy(const Extrinsic& extrinsic, AngleUnit unit);
Extrinsic parse_xyzrpy(std::string_view text, AngleUnit unit, const std::string& source_name);

// Input tolerates any whitespace, commas, semicolons and brackets. The last row must be 0 0 0 1
// and the 3x3 block a rotation within 1e-5 (so that a matrix printed with 6 significant digits,
// as by Eigen's operator<<, reads); it is then re-orthonormalised.
std::string format_matrix(const Extrinsic& extrinsic);
Extrinsic parse_matrix(std::string_view text, const std::string& source_name);

// The quaternion is normalised on input; a zero or non-finite one is rejected.
std::string format_quaternion(const Extrinsic& extrinsic);
Extrinsic parse_quaternion(std::string_view text, const std::string& source_name);

// The URDF and Autoware forms: urdf_joint.hpp and autoware_yaml.hpp, included above.

// Written with full precision; read from any precision (the reference writes 6 digits; its
// rotation is checked within 1e-5 as in the matrix form, then re-orthonormalised).
std::string format_reference(const Extrinsic& extrinsic);
Extrinsic parse_reference(std::string_view text, const std::string& source_name);

// Checks that a matrix read from input is a rotation within `tolerance` (orthonormal, det +1) and
// returns the nearest exact rotation; InputError at file/line otherwise.
Eigen::Matrix3d rotation_from_input(const Eigen::Matrix3d& matrix, double tolerance,
                                    const std::string& file, std::size_t line);

// Normalises a quaternion (w, x, y, z) read from input; InputError at file/line when it is zero or
// not finite.
Eigen::Quaterniond quaternion_from_input(double w, double x, double y, double z,
                                         const std::string& file, std::size_t line);

// ---- calibration results as extrinsics ------------------------------------------------------

// The parts of vehicle_from_sensor a result did not estimate, in the order x y z roll pitch yaw.
std::vector<std::string> unestimated_parts(const CalibrationResult& result);

// vehicle_from_sensor with unestimated parts as 0. Throws std::invalid_argument when the result
// is not ok: an insufficient_data result has no rotation to write, and 0 would be a guess.
Extrinsic extrinsic_from_result(const CalibrationResult& result,
                                const std::string& parent_frame = "base_link",
                                const std::string& child_frame = {});  // empty: result.sensor

// As the forms above, preceded by a comment naming the parts written as 0 (when there are any).
std::string format_result_autoware(const CalibrationResult& result,
                                   const std::string& parent_frame = "base_link",
                                   const std::string& child_frame = {});
std::string format_result_urdf(const CalibrationResult& result,
                               const std::string& parent_frame = "base_link",
                               const std::string& child_frame = {});
std::string format_result_reference(const CalibrationResult& result);

// A result JSON (io/result_json.hpp) as text: one sensor's object, or `calibrate all`'s object
// keyed by sensor. Recognised by its first character '{' and a "status" key at the top or one
// level down.
bool looks_like_result_json(std::string_view text);

// Its vehicle_from_sensor as extrinsic_from_result gives it (unestimated parts 0). From a keyed
// object, `sensor` picks the entry (needed when it holds several); the child frame is the entry's
// key, or the result's "sensor". InputError naming the source when the text is not a result, the
// sensor is missing or not chosen, or its status is not ok (there is no mounting to give).
Extrinsic extrinsic_from_result_json(std::string_view text, const std::string& source_name,
                                     const std::optional<std::string>& sensor = std::nullopt);

}  // namespace x2car::io
