#include "x2car/io/urdf_joint.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <map>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

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
  // Compared in place: building "<" + name made GCC 12 -O3 report a false -Wrestrict.
  for (std::size_t at = xml.find('<', from); at != xml.npos; at = xml.find('<', at + 1)) {
    if (xml.substr(at + 1, name.size()) != name) continue;
    const std::size_t after = at + 1 + name.size();
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
  const std::size_t line = line_number_at(xml, begin);
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
      throw InputError(source, line_number_at(text, begin), {},
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
  std::size_t line(const XmlTag& tag) const { return line_number_at(xml, tag.begin); }
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
  const bool angles = name == "rpy";
  Eigen::Vector3d values;
  for (int i = 0; i < 3; ++i) {
    values[i] = parse_double(fields[static_cast<std::size_t>(i)], where);
    check_plausible(values[i], angles ? kExtrinsicMaxRadians : kExtrinsicMaxValue,
                    fields[static_cast<std::size_t>(i)], angles ? "rad" : "m", where,
                    angles ? "URDF angles are radians" : "");
  }
  return values;
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

// Calls visit(urdf, joint, body_end) for each <joint> in order (its body ends at body_end), with
// comments and <transmission> blocks blanked out.
template <typename Visit>
void for_each_joint(std::string_view text, const std::string& source, Visit visit) {
  std::string xml = blank_out(std::string(text), "<!--", "-->", source);
  xml = blank_out(std::move(xml), "<transmission", "</transmission>", source);
  const UrdfContext urdf{xml, source};
  std::size_t from = 0;
  while (const auto joint = find_tag(xml, "joint", from, xml.size(), source)) {
    const std::size_t body_end =
        joint->self_closing ? joint->end : xml.find("</joint>", joint->end);
    if (body_end == xml.npos)
      throw InputError(source, urdf.line(*joint), {}, "<joint> without </joint>");
    visit(urdf, *joint, body_end);
    from = body_end;
  }
}

std::vector<Extrinsic> urdf_joints(std::string_view text, const std::string& source) {
  std::vector<Extrinsic> joints;
  for_each_joint(text, source,
                 [&](const UrdfContext& urdf, const XmlTag& joint, std::size_t body_end) {
                   joints.push_back(joint_extrinsic(urdf, joint, body_end));
                 });
  return joints;
}

// The value of attribute `name` inside the start tag [tag.begin, tag.end): [begin, end) between
// its quotes, or nullopt. Attribute names end at '=' or space, so "xyz" never matches "rpy".
std::optional<std::pair<std::size_t, std::size_t>> attribute_value(std::string_view xml,
                                                                   const XmlTag& tag,
                                                                   std::string_view name) {
  std::size_t at = tag.begin;
  while ((at = xml.find(name, at + 1)) != xml.npos && at < tag.end) {
    if (kXmlSpace.find(xml[at - 1]) == xml.npos) continue;
    std::size_t i = at + name.size();
    while (i < tag.end && kXmlSpace.find(xml[i]) != xml.npos) ++i;
    if (i >= tag.end || xml[i] != '=') continue;
    ++i;
    while (i < tag.end && kXmlSpace.find(xml[i]) != xml.npos) ++i;
    if (i >= tag.end || (xml[i] != '"' && xml[i] != '\'')) continue;
    const std::size_t close = xml.find(xml[i], i + 1);
    if (close == xml.npos || close >= tag.end) return std::nullopt;
    return std::pair{i + 1, close};
  }
  return std::nullopt;
}

}  // namespace

std::vector<UrdfJointOrigin> urdf_joint_origins(std::string_view text, const std::string& source) {
  std::vector<UrdfJointOrigin> origins;
  for_each_joint(
      text, source, [&](const UrdfContext& urdf, const XmlTag& joint, std::size_t body_end) {
        const Extrinsic extrinsic = joint_extrinsic(urdf, joint, body_end);  // checks it, as parse
        UrdfJointOrigin origin{extrinsic.parent_frame,
                               extrinsic.child_frame,
                               urdf.line(joint),
                               std::nullopt,
                               joint.end,
                               false};
        if (const auto tag = find_tag(urdf.xml, "origin", joint.end, body_end, source)) {
          origin.has_origin = true;
          origin.rpy_value = attribute_value(urdf.xml, *tag, "rpy");
          origin.insert_at = tag->begin + std::string_view("<origin").size();
        }
        origins.push_back(std::move(origin));
      });
  return origins;
}

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

bool has_urdf_joint(std::string_view text) { return has_xml_element(text, "joint"); }

}  // namespace x2car::io
