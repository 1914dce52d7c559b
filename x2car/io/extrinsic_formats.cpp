#include "x2car/io/extrinsic_formats.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <stdexcept>
#include <utility>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// A pasted matrix is exact up to its printing. The reference prints 6 significant digits, whose
// rounding (5e-7 per entry) moves R^T R by up to ~2e-6, so its text gets a looser bound.
constexpr double kMatrixRotationTolerance = 1e-6;
constexpr double kReferenceRotationTolerance = 1e-5;
constexpr double kLastRowTolerance = 1e-9;
// Below this length a quaternion holds no direction worth normalising.
constexpr double kMinQuaternionNorm = 1e-9;
constexpr std::string_view kReferenceMarker = "Extrinsic:";

struct FormatName {
  ExtrinsicFormat format;
  const char* name;
};
constexpr std::array<FormatName, 7> kFormatNames{{
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

// Exactly names.size() numbers; each error names its field.
std::vector<double> parse_tokens(std::span<const Token> tokens, std::span<const std::string> names,
                                 const std::string& source) {
  if (tokens.size() != names.size()) {
    throw InputError(source, fmt::format("expected {} numbers ({}), found {}", names.size(),
                                         join(names, " "), tokens.size()));
  }
  std::vector<double> values(tokens.size());
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    values[i] = parse_double(tokens[i].text, {source, tokens[i].line, names[i]});
  }
  return values;
}

std::vector<std::string> matrix_field_names() {
  std::vector<std::string> names;
  for (int row = 1; row <= 4; ++row) {
    for (int col = 1; col <= 4; ++col) names.push_back(fmt::format("row {} col {}", row, col));
  }
  return names;
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

std::size_t line_at(std::string_view text, std::size_t offset) {
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
}

std::string unestimated_note(const CalibrationResult& result) {
  const std::vector<std::string> parts = unestimated_parts(result);
  if (parts.empty()) return {};
  return fmt::format("x2car did not estimate these parts of {}; they are written as 0: {}",
                     result.sensor, join(parts));
}

// ---- a small reader for the URDF <joint> element; no XML library needed for one element ----

constexpr std::string_view kXmlSpace = " \t\r\n";

struct XmlTag {
  std::size_t begin = 0;  // offset of '<'
  std::size_t end = 0;    // offset just past '>'
  bool self_closing = false;
  std::map<std::string, std::string> attributes;
};

// Offset of the '>' that closes the tag opened at `from`; a '>' inside a quoted value is text.
std::size_t tag_close(std::string_view xml, std::size_t from) {
  char quote = 0;
  for (std::size_t i = from; i < xml.size(); ++i) {
    const char c = xml[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      return i;
    }
  }
  return std::string_view::npos;
}

// Offset of the next start tag `<name` as a whole name (<joint> is not <joint_state>).
std::size_t find_start_tag(std::string_view xml, std::string_view name, std::size_t from) {
  const std::string open = "<" + std::string(name);
  for (std::size_t at = xml.find(open, from); at != xml.npos; at = xml.find(open, at + 1)) {
    const std::size_t after = at + open.size();
    if (after == xml.size() || kXmlSpace.find(xml[after]) != xml.npos || xml[after] == '/' ||
        xml[after] == '>') {
      return at;
    }
  }
  return xml.npos;
}

bool has_xml_element(std::string_view text, std::string_view name) {
  return find_start_tag(text, name, 0) != text.npos;
}

constexpr std::array<std::pair<std::string_view, char>, 5> kXmlEntities{
    {{"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}, {"&amp;", '&'}}};

std::string xml_unescape(std::string_view text) {
  std::string plain;
  for (std::size_t i = 0; i < text.size();) {
    const auto* entity = std::find_if(kXmlEntities.begin(), kXmlEntities.end(), [&](const auto& e) {
      return text.substr(i).starts_with(e.first);
    });
    if (entity == kXmlEntities.end()) {
      plain += text[i++];
    } else {
      plain += entity->second;
      i += entity->first.size();
    }
  }
  return plain;
}

std::string xml_escape(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    const auto* entity = std::find_if(kXmlEntities.begin(), kXmlEntities.end(),
                                      [c](const auto& e) { return e.second == c; });
    if (entity == kXmlEntities.end()) {
      escaped += c;
    } else {
      escaped += entity->first;
    }
  }
  return escaped;
}

// The name="value" pairs inside a start tag, e.g. ` name="j" type='fixed'`.
std::map<std::string, std::string> parse_attributes(std::string_view inside,
                                                    const std::string& source, std::size_t line) {
  std::map<std::string, std::string> attributes;
  for (std::size_t i = inside.find_first_not_of(kXmlSpace); i != inside.npos;
       i = inside.find_first_not_of(kXmlSpace, i)) {
    const std::size_t name_end = std::min(inside.find_first_of("= \t\r\n", i), inside.size());
    const std::string name(inside.substr(i, name_end - i));
    const std::size_t equals = inside.find_first_not_of(kXmlSpace, name_end);
    const std::size_t quote = equals == inside.npos || inside[equals] != '='
                                  ? inside.npos
                                  : inside.find_first_not_of(kXmlSpace, equals + 1);
    if (quote == inside.npos || (inside[quote] != '"' && inside[quote] != '\'')) {
      throw InputError(source, line, name, "XML attribute without a quoted value");
    }
    const std::size_t close = inside.find(inside[quote], quote + 1);
    if (close == inside.npos) throw InputError(source, line, name, "unterminated XML attribute");
    attributes[name] = xml_unescape(inside.substr(quote + 1, close - quote - 1));
    i = close + 1;
  }
  return attributes;
}

// The first `<name ...>` start tag that begins in [from, to), if any.
std::optional<XmlTag> find_tag(std::string_view xml, std::string_view name, std::size_t from,
                               std::size_t to, const std::string& source) {
  const std::size_t begin = find_start_tag(xml, name, from);
  if (begin == xml.npos || begin >= to) return std::nullopt;
  const std::size_t line = line_at(xml, begin);
  const std::size_t close = tag_close(xml, begin);
  if (close == xml.npos) throw InputError(source, line, {}, fmt::format("unterminated <{}>", name));
  std::string_view inside = xml.substr(begin + 1 + name.size(), close - begin - 1 - name.size());
  XmlTag tag{begin, close + 1, inside.ends_with('/'), {}};
  if (tag.self_closing) inside.remove_suffix(1);
  tag.attributes = parse_attributes(inside, source, line);
  return tag;
}

// Blanks out `open ... close` ranges (XML comments; <transmission> blocks, whose <joint> children
// are not kinematic joints), keeping newlines so that line numbers stay right.
std::string blank_out(std::string text, std::string_view open, std::string_view close,
                      const std::string& source) {
  for (std::size_t begin = text.find(open); begin != text.npos; begin = text.find(open, begin)) {
    const std::size_t end = text.find(close, begin + open.size());
    if (end == text.npos) {
      throw InputError(source, line_at(text, begin), {},
                       fmt::format("'{}' without '{}'", open, close));
    }
    for (std::size_t i = begin; i < end + close.size(); ++i) {
      if (text[i] != '\n') text[i] = ' ';
    }
    begin = end + close.size();
  }
  return text;
}

struct UrdfContext {
  std::string_view xml;  // comments blanked out
  const std::string& source;
  std::size_t line(const XmlTag& tag) const { return line_at(xml, tag.begin); }
};

std::string link_of(const UrdfContext& urdf, const std::optional<XmlTag>& tag, const XmlTag& joint,
                    const char* element) {
  if (!tag) {
    throw InputError(urdf.source, urdf.line(joint), element,
                     fmt::format("the joint has no <{} link=\"...\"/>", element));
  }
  const auto link = tag->attributes.find("link");
  if (link == tag->attributes.end()) {
    throw InputError(urdf.source, urdf.line(*tag), element, "missing attribute 'link'");
  }
  return link->second;
}

// An <origin> attribute "a b c"; absent means zero, as in URDF.
Eigen::Vector3d origin_triple(const UrdfContext& urdf, const XmlTag& origin,
                              const std::string& name) {
  const auto value = origin.attributes.find(name);
  if (value == origin.attributes.end()) return Eigen::Vector3d::Zero();
  const FieldLocation where{urdf.source, urdf.line(origin), "origin " + name};
  const std::vector<std::string_view> fields = split_fields(value->second);
  if (fields.size() != 3) {
    throw InputError(where.file, where.line, where.field,
                     fmt::format("expected 3 numbers, found {}", fields.size()));
  }
  return {parse_double(fields[0], where), parse_double(fields[1], where),
          parse_double(fields[2], where)};
}

Extrinsic joint_extrinsic(const UrdfContext& urdf, const XmlTag& joint, std::size_t body_end) {
  const auto type = joint.attributes.find("type");
  if (type != joint.attributes.end() && type->second != "fixed") {
    throw InputError(
        urdf.source, urdf.line(joint), "type",
        fmt::format("joint type is '{}'; only a fixed joint is an extrinsic", type->second));
  }
  Extrinsic extrinsic;
  extrinsic.parent_frame = link_of(
      urdf, find_tag(urdf.xml, "parent", joint.end, body_end, urdf.source), joint, "parent");
  extrinsic.child_frame =
      link_of(urdf, find_tag(urdf.xml, "child", joint.end, body_end, urdf.source), joint, "child");
  if (const auto origin = find_tag(urdf.xml, "origin", joint.end, body_end, urdf.source)) {
    const Eigen::Vector3d xyz = origin_triple(urdf, *origin, "xyz");
    const Eigen::Vector3d rpy = origin_triple(urdf, *origin, "rpy");  // URDF: Rz Ry Rx, as §1
    extrinsic.parent_from_child = make_transform(EulerAngles{rpy.x(), rpy.y(), rpy.z()}, xyz);
  }
  return extrinsic;
}

std::vector<Extrinsic> urdf_joints(std::string_view text, const std::string& source) {
  std::string xml = blank_out(std::string(text), "<!--", "-->", source);
  xml = blank_out(std::move(xml), "<transmission", "</transmission>", source);
  const UrdfContext urdf{xml, source};
  std::vector<Extrinsic> joints;
  std::size_t from = 0;
  while (const auto joint = find_tag(xml, "joint", from, xml.size(), source)) {
    const std::size_t body_end =
        joint->self_closing ? joint->end : xml.find("</joint>", joint->end);
    if (body_end == xml.npos)
      throw InputError(source, urdf.line(*joint), {}, "<joint> without </joint>");
    joints.push_back(joint_extrinsic(urdf, *joint, body_end));
    from = body_end;
  }
  return joints;
}

// ---- Autoware sensor_kit_calibration.yaml -------------------------------------------------

constexpr std::array<const char*, 6> kAutowareKeys{"x", "y", "z", "roll", "pitch", "yaw"};

std::size_t yaml_line(const YAML::Mark& mark) {
  return mark.line < 0 ? 0 : static_cast<std::size_t>(mark.line) + 1;
}

YAML::Node load_yaml(std::string_view text, const std::string& source) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& error) {
    throw InputError(source, yaml_line(error.mark), {}, "invalid YAML: " + error.msg);
  }
}

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

// ---- names and dispatch -----------------------------------------------------------------------

const char* to_string(ExtrinsicFormat format) {
  for (const FormatName& entry : kFormatNames) {
    if (entry.format == format) return entry.name;
  }
  return "unknown";
}

ExtrinsicFormat extrinsic_format_from_string(std::string_view name) {
  for (const FormatName& entry : kFormatNames) {
    if (name == entry.name) return entry.format;
  }
  throw std::invalid_argument(fmt::format("unknown extrinsic format '{}'; expected one of {}", name,
                                          join(extrinsic_format_names())));
}

std::vector<std::string> extrinsic_format_names() {
  std::vector<std::string> names;
  for (const FormatName& entry : kFormatNames) names.emplace_back(entry.name);
  return names;
}

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
  if (has_xml_element(text, "joint")) return ExtrinsicFormat::kUrdf;
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

// ---- xyzrpy, matrix, quaternion, reference ------------------------------------------------

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
  static const std::vector<std::string> kNames{"x", "y", "z", "roll", "pitch", "yaw"};
  const std::vector<double> v = parse_tokens(number_tokens(text), kNames, source_name);
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
  const std::vector<double> values = parse_tokens(tokens, matrix_field_names(), source_name);
  return extrinsic_from_matrix(values, kMatrixRotationTolerance, source_name, 0);
}

std::string format_quaternion(const Extrinsic& extrinsic) {
  const Eigen::Vector3d t = extrinsic.parent_from_child.translation();
  Eigen::Quaterniond q(extrinsic.parent_from_child.linear());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one of the two equal quaternions, for diffs
  return format_numbers({t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) + "\n";
}

Extrinsic parse_quaternion(std::string_view text, const std::string& source_name) {
  static const std::vector<std::string> kNames{"x", "y", "z", "qx", "qy", "qz", "qw"};
  const std::vector<Token> tokens = number_tokens(text);
  const std::vector<double> v = parse_tokens(tokens, kNames, source_name);
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
  const std::size_t first_line = line_at(text, marker);
  std::vector<Token> tokens = split_number_tokens(text.substr(marker + kReferenceMarker.size()));
  for (Token& token : tokens) token.line += first_line - 1;
  if (tokens.size() < 16) {
    throw InputError(
        source_name, first_line, {},
        fmt::format("expected 16 numbers after '{}', found {}", kReferenceMarker, tokens.size()));
  }
  tokens.resize(16);
  const std::vector<double> values = parse_tokens(tokens, matrix_field_names(), source_name);
  return extrinsic_from_matrix(values, kReferenceRotationTolerance, source_name, first_line);
}

// ---- URDF ------------------------------------------------------------------------------------

std::string format_urdf(const Extrinsic& extrinsic) {
  const Eigen::Vector3d t = extrinsic.parent_from_child.translation();
  const EulerAngles a = euler_from_rotation(extrinsic.parent_from_child.linear());
  return fmt::format(
      "<joint name=\"{}_joint\" type=\"fixed\">\n  <parent link=\"{}\"/>\n  <child link=\"{}\"/>\n"
      "  <origin xyz=\"{}\" rpy=\"{}\"/>\n</joint>\n",
      xml_escape(extrinsic.child_frame), xml_escape(extrinsic.parent_frame),
      xml_escape(extrinsic.child_frame), format_numbers({t.x(), t.y(), t.z()}),
      format_numbers({a.roll, a.pitch, a.yaw}));
}

Extrinsic parse_urdf(std::string_view text, const std::string& source_name,
                     const std::optional<std::string>& child_link) {
  const std::vector<Extrinsic> joints = urdf_joints(text, source_name);
  if (joints.empty()) throw InputError(source_name, "no <joint> element found");
  std::vector<std::string> children;
  for (const Extrinsic& joint : joints) children.push_back(joint.child_frame);
  if (child_link) {
    const auto found = std::find(children.begin(), children.end(), *child_link);
    if (found != children.end()) return joints[static_cast<std::size_t>(found - children.begin())];
    throw InputError(source_name, fmt::format("no joint with child link '{}'; child links: {}",
                                              *child_link, join(children)));
  }
  if (joints.size() > 1) {
    throw InputError(source_name, fmt::format("{} joints found (child links: {}); name the one to "
                                              "read",
                                              joints.size(), join(children)));
  }
  return joints.front();
}

// ---- Autoware ---------------------------------------------------------------------------------

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
  return autoware_child(file.parent, children.front(), file.children[children.front()],
                        source_name);
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

}  // namespace x2car::io
