#include "x2car/io/extrinsic_formats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <span>
#include <stdexcept>
#include <utility>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// A pasted matrix is exact up to its printing. Six significant digits (the default of ostream and
// so of Eigen's operator<<, and what the reference writes) round each entry by up to 5e-7, which
// moves R^T R by up to ~2e-6; an entry off by 1e-4 or more is a different matrix, not rounding.
constexpr double kPrintedRotationTolerance = 1e-5;
constexpr double kLastRowTolerance = 1e-9;
// Below this length a quaternion holds no direction worth normalising.
constexpr double kMinQuaternionNorm = 1e-9;
constexpr std::string_view kReferenceMarker = "Extrinsic:";

constexpr std::array<EnumName<ExtrinsicFormat>, 7> kExtrinsicFormatNames{{
    {ExtrinsicFormat::kXyzRpyDeg, "xyzrpy-deg"},
    {ExtrinsicFormat::kXyzRpyRad, "xyzrpy-rad"},
    {ExtrinsicFormat::kMatrix, "matrix"},
    {ExtrinsicFormat::kQuaternion, "quaternion"},
    {ExtrinsicFormat::kUrdf, "urdf"},
    {ExtrinsicFormat::kAutoware, "autoware"},
    {ExtrinsicFormat::kReference, "reference"},
}};

Extrinsic make_extrinsic(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Extrinsic extrinsic;
  extrinsic.parent_from_child = make_transform(rotation, translation);
  return extrinsic;
}

// The numeric tokens of a text, leaving out '#' comment lines; each keeps its line number.
std::vector<Token> number_tokens(std::string_view text) {
  std::vector<Token> tokens;
  for (const TextLine& line : split_lines(text)) {
    for (Token token : split_number_tokens(line.text)) {
      token.line = line.number;
      tokens.push_back(token);
    }
  }
  return tokens;
}

// The numbers of a text form: each one's name, for an error about that field, and how an error
// about their count describes them all ("x y z roll pitch yaw", "a 4x4 matrix, row-major").
struct NumberLayout {
  std::vector<std::string> names;
  std::string description;
};

NumberLayout named_numbers(std::vector<std::string> names) {
  std::string description = join(names, " ");
  return {std::move(names), std::move(description)};
}

// Exactly layout.names.size() numbers; each error names its field.
std::vector<double> parse_tokens(std::span<const Token> tokens, const NumberLayout& layout,
                                 const std::string& source) {
  const std::vector<std::string>& names = layout.names;
  if (tokens.size() != names.size()) {
    throw InputError(source, fmt::format("expected {} numbers ({}), found {}", names.size(),
                                         layout.description, tokens.size()));
  }
  std::vector<double> values(tokens.size());
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const FieldLocation where{source, tokens[i].line, names[i]};
    values[i] = parse_double(tokens[i].text, where);
    check_plausible(values[i], kExtrinsicMaxValue, tokens[i].text, "", where);
  }
  return values;
}

const NumberLayout& matrix_layout() {
  static const NumberLayout kLayout = [] {
    NumberLayout layout{{}, "a 4x4 matrix, row-major"};
    for (int row = 1; row <= 4; ++row) {
      for (int col = 1; col <= 4; ++col) {
        layout.names.push_back(fmt::format("row {} col {}", row, col));
      }
    }
    return layout;
  }();
  return kLayout;
}

Extrinsic extrinsic_from_matrix(std::span<const double> row_major, double rotation_tolerance,
                                const std::string& source, std::size_t line) {
  const Eigen::Matrix4d matrix =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(row_major.data());
  const Eigen::RowVector4d last_row = matrix.row(3);
  if ((last_row - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > kLastRowTolerance) {
    throw InputError(source, line, "row 4",
                     fmt::format("the last row must be 0 0 0 1, found {} {} {} {}", last_row(0),
                                 last_row(1), last_row(2), last_row(3)));
  }
  const Eigen::Matrix3d rotation =
      rotation_from_input(matrix.topLeftCorner<3, 3>(), rotation_tolerance, source, line);
  return make_extrinsic(rotation, matrix.topRightCorner<3, 1>());
}

std::string row_text(const Eigen::Matrix4d& matrix, int row, std::string_view separator) {
  return format_numbers({matrix(row, 0), matrix(row, 1), matrix(row, 2), matrix(row, 3)},
                        separator);
}

bool is_number(std::string_view text) {
  try {
    parse_double(text, {});
    return true;
  } catch (const InputError&) {
    return false;
  }
}

bool has_reference_marker(std::string_view text) {
  for (const TextLine& line : split_lines(text)) {
    if (trim(line.text).starts_with(kReferenceMarker)) return true;
  }
  return false;
}

std::string unestimated_note(const CalibrationResult& result) {
  const std::vector<std::string> parts = unestimated_parts(result);
  if (parts.empty()) return {};
  return fmt::format("x2car did not estimate these parts of {}; they are written as 0: {}",
                     result.sensor, join(parts));
}

}  // namespace

// ---- names and dispatch -----------------------------------------------------------------------

const char* to_string(ExtrinsicFormat format) {
  return enum_to_string(kExtrinsicFormatNames, format);
}

ExtrinsicFormat extrinsic_format_from_string(std::string_view name) {
  return enum_from_string(kExtrinsicFormatNames, name, "extrinsic format");
}

std::vector<std::string> extrinsic_format_names() { return enum_names(kExtrinsicFormatNames); }

std::string format_extrinsic(const Extrinsic& extrinsic, ExtrinsicFormat format) {
  switch (format) {
    case ExtrinsicFormat::kXyzRpyDeg:
      return format_xyzrpy(extrinsic, AngleUnit::kDegrees);
    case ExtrinsicFormat::kXyzRpyRad:
      return format_xyzrpy(extrinsic, AngleUnit::kRadians);
    case ExtrinsicFormat::kMatrix:
      return format_matrix(extrinsic);
    case ExtrinsicFormat::kQuaternion:
      return format_quaternion(extrinsic);
    case ExtrinsicFormat::kUrdf:
      return format_urdf(extrinsic);
    case ExtrinsicFormat::kAutoware:
      return format_autoware(extrinsic);
    case ExtrinsicFormat::kReference:
      return format_reference(extrinsic);
  }
  throw std::invalid_argument("unknown extrinsic format");
}

Extrinsic parse_extrinsic(std::string_view text, ExtrinsicFormat format,
                          const std::string& source_name) {
  switch (format) {
    case ExtrinsicFormat::kXyzRpyDeg:
      return parse_xyzrpy(text, AngleUnit::kDegrees, source_name);
    case ExtrinsicFormat::kXyzRpyRad:
      return parse_xyzrpy(text, AngleUnit::kRadians, source_name);
    case ExtrinsicFormat::kMatrix:
      return parse_matrix(text, source_name);
    case ExtrinsicFormat::kQuaternion:
      return parse_quaternion(text, source_name);
    case ExtrinsicFormat::kUrdf:
      return parse_urdf(text, source_name);
    case ExtrinsicFormat::kAutoware:
      return parse_autoware(text, source_name);
    case ExtrinsicFormat::kReference:
      return parse_reference(text, source_name);
  }
  throw std::invalid_argument("unknown extrinsic format");
}

std::optional<ExtrinsicFormat> detect_extrinsic_format(std::string_view text) {
  if (has_urdf_joint(text)) return ExtrinsicFormat::kUrdf;
  if (has_reference_marker(text)) return ExtrinsicFormat::kReference;
  if (looks_like_autoware(text)) return ExtrinsicFormat::kAutoware;
  const std::vector<Token> tokens = number_tokens(text);
  for (const Token& token : tokens) {
    if (!is_number(token.text)) return std::nullopt;
  }
  if (tokens.size() == 16) return ExtrinsicFormat::kMatrix;
  if (tokens.size() == 7) return ExtrinsicFormat::kQuaternion;
  return std::nullopt;  // 6 numbers: degrees or radians? Only the user knows.
}

// ---- xyzrpy, matrix, quaternion, reference -----------------------------------------------------

std::string format_xyzrpy(const Extrinsic& extrinsic, AngleUnit unit) {
  const Eigen::Vector3d t = extrinsic.parent_from_child.translation();
  const EulerAngles angles = euler_from_rotation(extrinsic.parent_from_child.linear());
  const auto shown = [unit](double radians) {
    return unit == AngleUnit::kDegrees ? deg_from_rad(radians) : radians;
  };
  return format_numbers(
             {t.x(), t.y(), t.z(), shown(angles.roll), shown(angles.pitch), shown(angles.yaw)}) +
         "\n";
}

Extrinsic parse_xyzrpy(std::string_view text, AngleUnit unit, const std::string& source_name) {
  static const NumberLayout kLayout = named_numbers({"x", "y", "z", "roll", "pitch", "yaw"});
  const std::vector<Token> tokens = number_tokens(text);
  const std::vector<double> v = parse_tokens(tokens, kLayout, source_name);
  for (std::size_t i = 3; i < 6 && unit == AngleUnit::kRadians; ++i) {
    check_plausible(v[i], kExtrinsicMaxRadians, tokens[i].text, "rad",
                    {source_name, tokens[i].line, kLayout.names[i]}, "degrees? use xyzrpy-deg");
  }
  const auto radians = [unit](double value) {
    return unit == AngleUnit::kDegrees ? rad_from_deg(value) : value;
  };
  const EulerAngles angles{radians(v[3]), radians(v[4]), radians(v[5])};
  return make_extrinsic(rotation_from_euler(angles), Eigen::Vector3d(v[0], v[1], v[2]));
}

std::string format_matrix(const Extrinsic& extrinsic) {
  const Eigen::Matrix4d matrix = extrinsic.parent_from_child.matrix();
  std::string text;
  for (int row = 0; row < 4; ++row) text += row_text(matrix, row, " ") + "\n";
  return text;
}

Extrinsic parse_matrix(std::string_view text, const std::string& source_name) {
  const std::vector<Token> tokens = number_tokens(text);
  const std::vector<double> values = parse_tokens(tokens, matrix_layout(), source_name);
  return extrinsic_from_matrix(values, kPrintedRotationTolerance, source_name, 0);
}

std::string format_quaternion(const Extrinsic& extrinsic) {
  const Eigen::Vector3d t = extrinsic.parent_from_child.translation();
  Eigen::Quaterniond q(extrinsic.parent_from_child.linear());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one of the two equal quaternions, for diffs
  return format_numbers({t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) + "\n";
}

Extrinsic parse_quaternion(std::string_view text, const std::string& source_name) {
  static const NumberLayout kLayout = named_numbers({"x", "y", "z", "qx", "qy", "qz", "qw"});
  const std::vector<Token> tokens = number_tokens(text);
  const std::vector<double> v = parse_tokens(tokens, kLayout, source_name);
  const Eigen::Quaterniond q =
      quaternion_from_input(v[6], v[3], v[4], v[5], source_name, tokens.back().line);
  return make_extrinsic(q.toRotationMatrix(), Eigen::Vector3d(v[0], v[1], v[2]));
}

std::string format_reference(const Extrinsic& extrinsic) {
  const Eigen::Matrix4d m = extrinsic.parent_from_child.matrix();
  return fmt::format("{}\n[{}],[{}],[{}],[0,0,0,1]\n", kReferenceMarker, row_text(m, 0, ","),
                     row_text(m, 1, ","), row_text(m, 2, ","));
}

// Reads the 16 numbers after the last "Extrinsic:" marker: when the tool printed several, the
// last one is its final estimate. Whatever follows the 16 numbers is not ours to read.
Extrinsic parse_reference(std::string_view text, const std::string& source_name) {
  const std::size_t marker = text.rfind(kReferenceMarker);
  if (marker == text.npos) {
    throw InputError(source_name, fmt::format("no line '{}' found", kReferenceMarker));
  }
  const std::size_t first_line = line_number_at(text, marker);
  std::vector<Token> tokens = split_number_tokens(text.substr(marker + kReferenceMarker.size()));
  for (Token& token : tokens) token.line += first_line - 1;
  if (tokens.size() < 16) {
    throw InputError(source_name, first_line, {},
                     fmt::format("expected 16 numbers ({}) after '{}', found {}",
                                 matrix_layout().description, kReferenceMarker, tokens.size()));
  }
  tokens.resize(16);
  const std::vector<double> values = parse_tokens(tokens, matrix_layout(), source_name);
  return extrinsic_from_matrix(values, kPrintedRotationTolerance, source_name, first_line);
}

// ---- checked geometry from input ------------------------------------------------------------

Eigen::Matrix3d rotation_from_input(const Eigen::Matrix3d& matrix, double tolerance,
                                    const std::string& file, std::size_t line) {
  if (!is_rotation(matrix, tolerance)) {
    const double off = (matrix.transpose() * matrix - Eigen::Matrix3d::Identity()).norm();
    throw InputError(file, line, {},
                     fmt::format("not a rotation matrix: |R^T R - I| = {:.3g}, det R = {:.6g} "
                                 "(tolerance {:.3g})",
                                 off, matrix.determinant(), tolerance));
  }
  return nearest_rotation(matrix);
}

Eigen::Quaterniond quaternion_from_input(double w, double x, double y, double z,
                                         const std::string& file, std::size_t line) {
  const Eigen::Quaterniond q(w, x, y, z);
  if (!(q.norm() > kMinQuaternionNorm) || !q.coeffs().allFinite()) {
    throw InputError(file, line, "quaternion",
                     fmt::format("quaternion ({} {} {} {}) has no direction", x, y, z, w));
  }
  return q.normalized();
}

// ---- calibration results --------------------------------------------------------------------

std::vector<std::string> unestimated_parts(const CalibrationResult& result) {
  const std::array<std::pair<const char*, const std::optional<double>*>, 6> parts{{
      {"x", &result.x},
      {"y", &result.y},
      {"z", &result.z},
      {"roll", &result.roll},
      {"pitch", &result.pitch},
      {"yaw", &result.yaw},
  }};
  std::vector<std::string> missing;
  for (const auto& [name, value] : parts) {
    if (!value->has_value()) missing.emplace_back(name);
  }
  return missing;
}

Extrinsic extrinsic_from_result(const CalibrationResult& result, const std::string& parent_frame,
                                const std::string& child_frame) {
  if (!result.ok()) {
    throw std::invalid_argument(
        fmt::format("the {} result is {} ({}); there is no calibration to "
                    "write",
                    result.sensor, to_string(result.status), result.reason));
  }
  Extrinsic extrinsic;
  extrinsic.parent_frame = parent_frame;
  if (!child_frame.empty() || !result.sensor.empty()) {
    extrinsic.child_frame = child_frame.empty() ? result.sensor : child_frame;
  }
  const Eigen::Vector3d translation(result.x.value_or(0.0), result.y.value_or(0.0),
                                    result.z.value_or(0.0));
  extrinsic.parent_from_child = make_transform(result.angles_or_zero(), translation);
  return extrinsic;
}

std::string format_result_autoware(const CalibrationResult& result, const std::string& parent_frame,
                                   const std::string& child_frame) {
  const Extrinsic extrinsic = extrinsic_from_result(result, parent_frame, child_frame);
  const std::string note = unestimated_note(result);
  return (note.empty() ? "" : "# " + note + "\n") + format_autoware(extrinsic);
}

std::string format_result_urdf(const CalibrationResult& result, const std::string& parent_frame,
                               const std::string& child_frame) {
  const Extrinsic extrinsic = extrinsic_from_result(result, parent_frame, child_frame);
  const std::string note = unestimated_note(result);
  return (note.empty() ? "" : "<!-- " + note + " -->\n") + format_urdf(extrinsic);
}

std::string format_result_reference(const CalibrationResult& result) {
  const Extrinsic extrinsic = extrinsic_from_result(result);
  const std::string note = unestimated_note(result);
  return (note.empty() ? "" : "# " + note + "\n") + format_reference(extrinsic);
}

bool looks_like_result_json(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos || text[first] != '{') return false;
  const Json json = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object()) return false;
  if (json.contains("status")) return true;
  return std::ranges::any_of(json.items(), [](const auto& item) {
    return item.value().is_object() && item.value().contains("status");
  });
}

Extrinsic extrinsic_from_result_json(std::string_view text, const std::string& source_name,
                                     const std::optional<std::string>& sensor) {
  const Json json = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object()) throw InputError(source_name, "is not a JSON object (a result file)");
  std::string name;
  const Json* entry = &json;
  if (!json.contains("status")) {
    std::vector<std::string> names;
    for (const auto& item : json.items()) names.push_back(item.key());
    if (sensor) {
      if (!json.contains(*sensor)) {
        throw InputError(source_name,
                         fmt::format("holds no sensor '{}'; it holds: {}", *sensor, join(names)));
      }
      name = *sensor;
    } else if (names.size() == 1) {
      name = names.front();
    } else {
      throw InputError(source_name,
                       fmt::format("holds the results of several sensors ({}): pick one with "
                                   "--child",
                                   join(names)));
    }
    entry = &json.at(name);
  }
  const CalibrationResult result = result_from_json(*entry, source_name);
  if (name.empty()) name = sensor.value_or(result.sensor);
  if (!result.ok()) {
    throw InputError(source_name, fmt::format("the result of {} is {}: there is no mounting to "
                                              "convert ({})",
                                              name, to_string(result.status), result.reason));
  }
  return extrinsic_from_result(result, "base_link", name);
}

}  // namespace x2car::io
