#include "x2car/io/ins_csv.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// ---- columns -----------------------------------------------------------------------------------

// The quantities a column can give; each needs at most one column.
// clang-format off
enum class Slot { kTime, kX, kY, kZ, kLat, kLon, kAlt, kVe, kVn, kVu, kRoll, kPitch, kYaw, kStatus,
                  kQx, kQy, kQz, kQw, kCount };
// clang-format on
constexpr std::size_t kSlotCount = static_cast<std::size_t>(Slot::kCount);

struct Alias {
  std::string_view name;  // lower case
  Slot slot;
};

constexpr std::array<Alias, 50> kAliases{{
    {"time", Slot::kTime},
    {"time_s", Slot::kTime},
    {"time_ns", Slot::kTime},
    {"time_us", Slot::kTime},
    {"time_ms", Slot::kTime},
    {"qx", Slot::kQx},
    {"qy", Slot::kQy},
    {"qz", Slot::kQz},
    {"qw", Slot::kQw},
    {"quat_x", Slot::kQx},
    {"quat_y", Slot::kQy},
    {"quat_z", Slot::kQz},
    {"quat_w", Slot::kQw},
    {"orientation_x", Slot::kQx},
    {"orientation_y", Slot::kQy},
    {"orientation_z", Slot::kQz},
    {"orientation_w", Slot::kQw},
    {"x", Slot::kX},
    {"east", Slot::kX},
    {"y", Slot::kY},
    {"north", Slot::kY},
    {"z", Slot::kZ},
    {"up", Slot::kZ},
    {"lat", Slot::kLat},
    {"latitude", Slot::kLat},
    {"lon", Slot::kLon},
    {"longitude", Slot::kLon},
    {"alt", Slot::kAlt},
    {"altitude", Slot::kAlt},
    {"vx", Slot::kVe},
    {"ve", Slot::kVe},
    {"v_east", Slot::kVe},
    {"vy", Slot::kVn},
    {"vn", Slot::kVn},
    {"v_north", Slot::kVn},
    {"vz", Slot::kVu},
    {"vu", Slot::kVu},
    {"v_up", Slot::kVu},
    {"vel_e", Slot::kVe},
    {"vel_n", Slot::kVn},
    {"vel_u", Slot::kVu},
    {"vel_east", Slot::kVe},
    {"vel_north", Slot::kVn},
    {"vel_up", Slot::kVu},
    {"roll", Slot::kRoll},
    {"pitch", Slot::kPitch},
    {"yaw", Slot::kYaw},
    {"heading", Slot::kYaw},
    {"azimuth", Slot::kYaw},
    {"status", Slot::kStatus},
}};

constexpr std::array<Slot, 3> kEnuSlots{Slot::kX, Slot::kY, Slot::kZ};
constexpr std::array<Slot, 3> kGeodeticSlots{Slot::kLat, Slot::kLon, Slot::kAlt};
constexpr std::array<Slot, 3> kVelocitySlots{Slot::kVe, Slot::kVn, Slot::kVu};
constexpr std::array<Slot, 3> kEulerSlots{Slot::kRoll, Slot::kPitch, Slot::kYaw};
// world_from_ins as a quaternion in ENU (ROS's orientation), instead of roll, pitch and yaw.
constexpr std::array<Slot, 4> kQuaternionSlots{Slot::kQx, Slot::kQy, Slot::kQz, Slot::kQw};

std::size_t index_of(Slot slot) { return static_cast<std::size_t>(slot); }
bool is_angle(Slot slot) {
  return slot == Slot::kRoll || slot == Slot::kPitch || slot == Slot::kYaw;
}
bool is_lat_lon(Slot slot) { return slot == Slot::kLat || slot == Slot::kLon; }

std::optional<Slot> slot_of(std::string_view lower_name) {
  for (const Alias& alias : kAliases) {
    if (alias.name == lower_name) return alias.slot;
  }
  return std::nullopt;
}

// "'x' or 'east'": the names a missing column may have.
std::string accepted_names(Slot slot) {
  std::vector<std::string> names;
  for (const Alias& alias : kAliases) {
    if (alias.slot == slot) names.push_back(fmt::format("'{}'", alias.name));
  }
  return join(names, " or ");
}

struct Column {
  std::size_t index = 0;  // zero-based position in a row
  std::string name;       // as the header writes it, for messages
  std::string alias;      // lower case, without a unit suffix ("time_ns", "heading")
  double scale = 1.0;     // to radians (angles) or degrees (latitude, longitude)
};

std::string lower_case(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

// The slot and scale of a header name; angles and latitude/longitude may carry `_deg` or `_rad`.
std::optional<std::pair<Slot, Column>> match_column(std::string_view written, std::size_t index,
                                                    const InsCsvOptions& options) {
  const std::string lower = lower_case(written);
  const double default_angle_scale =
      options.angle_unit == AngleUnit::kDegrees ? rad_from_deg(1.0) : 1.0;
  if (const std::optional<Slot> slot = slot_of(lower)) {
    return std::pair{*slot, Column{index, std::string(written), lower,
                                   is_angle(*slot) ? default_angle_scale : 1.0}};
  }
  for (const bool degrees : {true, false}) {
    const std::string_view suffix = degrees ? "_deg" : "_rad";
    if (!lower.ends_with(suffix)) continue;
    const std::string alias = lower.substr(0, lower.size() - suffix.size());
    const std::optional<Slot> slot = slot_of(alias);
    if (!slot || !(is_angle(*slot) || is_lat_lon(*slot))) return std::nullopt;
    const double scale =
        is_angle(*slot) ? (degrees ? rad_from_deg(1.0) : 1.0) : (degrees ? 1.0 : deg_from_rad(1.0));
    return std::pair{*slot, Column{index, std::string(written), alias, scale}};
  }
  return std::nullopt;
}

// ---- header ------------------------------------------------------------------------------------

struct Layout {
  std::size_t header_line = 0;
  std::size_t field_count = 0;
  Delimiter delimiter = Delimiter::kAuto;
  std::vector<std::string> ignored;  // header names the reader does not use, "'name' (column)"
  std::array<std::optional<Column>, kSlotCount> columns;
  bool geodetic = false;
  bool time_ns = false;  // an integer count since the Unix epoch: time_ns, time_us or time_ms
  std::int64_t ns_per_count = 1;
  bool quaternion = false;
  bool yaw_is_azimuth = false;

  const std::optional<Column>& operator[](Slot slot) const { return columns[index_of(slot)]; }
  bool has_any(std::span<const Slot> slots) const {
    return std::any_of(slots.begin(), slots.end(), [&](Slot s) { return (*this)[s].has_value(); });
  }
};

void add_missing(const Layout& layout, std::span<const Slot> slots, std::vector<std::string>& out,
                 std::string_view note = {}) {
  for (const Slot slot : slots) {
    if (!layout[slot]) out.push_back(accepted_names(slot) + std::string(note));
  }
}

// Every required column that is absent, as one message listing what is accepted.
void check_required(const Layout& layout, const std::string& source) {
  std::vector<std::string> missing;
  const std::array<Slot, 1> time{Slot::kTime};
  add_missing(layout, time, missing);
  const bool enu = layout.has_any(kEnuSlots);
  const bool geodetic = layout.has_any(kGeodeticSlots);
  if (!enu && !geodetic) {
    missing.emplace_back(
        "a position: 'x,y,z' or 'east,north,up' (ENU [m]), or 'lat,lon,alt' or "
        "'latitude,longitude,altitude' ([deg], [deg], [m])");
  } else if (enu != geodetic) {  // both: reported after this check
    add_missing(layout, enu ? kEnuSlots : kGeodeticSlots, missing);
  }
  if (layout.has_any(kVelocitySlots)) {
    add_missing(layout, kVelocitySlots, missing, " (velocity is optional, but needs all three)");
  }
  if (layout.has_any(kQuaternionSlots) && !layout.has_any(kEulerSlots)) {
    add_missing(layout, kQuaternionSlots, missing, " (an attitude quaternion needs all four)");
  } else {
    add_missing(layout, kEulerSlots, missing);
  }
  if (missing.empty()) return;
  throw InputError(source, layout.header_line, {},
                   fmt::format("missing column(s): {} (names are case-insensitive; angles in "
                               "radians, or in degrees with a '_deg' suffix)",
                               join(missing, "; ")));
}

Layout parse_header(const TextLine& header, const InsCsvOptions& options,
                    const std::string& source) {
  Layout layout;
  layout.delimiter = detect_delimiter(header.text);
  const std::vector<std::string_view> names = split_fields(header.text, layout.delimiter);
  layout.header_line = header.number;
  layout.field_count = names.size();
  std::optional<InputError> duplicate;  // reported after the missing columns
  // --columns: a header name the user mapped reads as the quantity it was mapped to.
  std::vector<std::string> mapped_names;
  for (const auto& mapping : options.column_names) {
    // Named, not bound: a lambda may not capture a structured binding before C++20's clang 16.
    const std::string& quantity = mapping.first;
    const std::string& header_name = mapping.second;
    const bool present = std::ranges::any_of(names, [&](std::string_view name) {
      return lower_case(trim(name)) == lower_case(header_name);
    });
    if (!present) {
      throw InputError(source, header.number, header_name,
                       fmt::format("the column mapping names '{}' for {}, but the header has no "
                                   "such column",
                                   header_name, quantity));
    }
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::string_view written = names[i];
    for (const auto& [quantity, header_name] : options.column_names) {
      if (lower_case(trim(names[i])) == lower_case(header_name)) written = quantity;
    }
    std::optional<std::pair<Slot, Column>> match = match_column(written, i, options);
    if (match && written != names[i]) match->second.name = std::string(names[i]);
    if (!match) {  // unknown columns are ignored, and named in a notice
      layout.ignored.push_back(fmt::format("{} ({})", quote_field(names[i]), i + 1));
      continue;
    }
    std::optional<Column>& column = layout.columns[index_of(match->first)];
    if (column && !duplicate) {
      duplicate = InputError(source, header.number, std::string(names[i]),
                             fmt::format("columns '{}' ({}) and '{}' ({}) give the same quantity; "
                                         "keep one",
                                         column->name, column->index + 1, names[i], i + 1));
    }
    if (!column) column = std::move(match->second);
  }
  layout.geodetic = !layout.has_any(kEnuSlots) && layout.has_any(kGeodeticSlots);
  check_required(layout, source);
  if (duplicate) throw *duplicate;
  if (layout.has_any(kEnuSlots) && layout.has_any(kGeodeticSlots)) {
    const auto first = [&](std::span<const Slot> slots) {
      for (const Slot s : slots) {
        if (layout[s]) return layout[s]->name;
      }
      return std::string();
    };
    const std::string geodetic_name = first(kGeodeticSlots);
    throw InputError(source, header.number, geodetic_name,
                     fmt::format("both an ENU position ('{}') and a geodetic one ('{}'); keep one",
                                 first(kEnuSlots), geodetic_name));
  }
  const std::string& time_alias = layout[Slot::kTime]->alias;
  layout.time_ns = time_alias == "time_ns" || time_alias == "time_us" || time_alias == "time_ms";
  layout.ns_per_count = time_alias == "time_ms" ? 1'000'000 : time_alias == "time_us" ? 1'000 : 1;
  if (layout.has_any(kQuaternionSlots) && layout.has_any(kEulerSlots)) {
    throw InputError(source, header.number, layout[Slot::kQw] ? layout[Slot::kQw]->name : "qw",
                     "both roll/pitch/yaw and an attitude quaternion; keep one");
  }
  layout.quaternion = layout.has_any(kQuaternionSlots);
  layout.yaw_is_azimuth =
      !layout.quaternion &&
      (options.yaw_convention ? *options.yaw_convention == YawConvention::kAzimuth
                              : layout[Slot::kYaw]->alias != "yaw");
  return layout;
}

// ---- rows --------------------------------------------------------------------------------------

struct ParsedRow {
  InsRecord record;  // position_enu unset for a geodetic file; time unset for time_ns
  std::int64_t time_ns = 0;
  GeodeticPosition geodetic;
};

ParsedRow parse_row(const TextLine& line, const Layout& layout, const std::string& source) {
  const std::vector<std::string_view> fields = split_exact_fields(
      line, layout.field_count, source,
      fmt::format(" as in the header (line {})", layout.header_line), layout.delimiter);
  const auto where = [&](Slot s) { return FieldLocation{source, line.number, layout[s]->name}; };
  const auto value = [&](Slot s) {
    return parse_double(fields[layout[s]->index], where(s)) * layout[s]->scale;
  };
  // An angle read as radians beyond +-2 pi is surely in degrees (issue 11: such a file was
  // reported downstream as "4912 reversing").
  const auto angle = [&](Slot s) {
    const double radians = value(s);
    if (std::abs(radians) > kInsMaxAngle) {
      const std::string_view text = fields[layout[s]->index];
      throw InputError(
          source, line.number, layout[s]->name,
          layout[s]->scale == 1.0
              ? fmt::format("{} is beyond +-2 pi, so not an angle in radians; if the column "
                            "holds degrees, name it '{}_deg' (or read angles in degrees: "
                            "calibrate ins --angle-unit deg)",
                            text, layout[s]->alias)
              : fmt::format("{} deg is beyond +-360 deg, not an angle", text));
    }
    return radians;
  };
  // Values no car's device reports (issue 11: 1e308 travelled on and came back as a 309-digit
  // number).
  const auto bounded = [&](Slot s, double limit, const char* unit) {
    const double v = value(s);
    check_plausible(v, limit, fields[layout[s]->index], unit, where(s));
    return v;
  };
  ParsedRow row;
  InsRecord& r = row.record;
  if (layout.time_ns) {
    const std::int64_t count =
        parse_integer(fields[layout[Slot::kTime]->index], where(Slot::kTime));
    if (std::abs(count) > std::numeric_limits<std::int64_t>::max() / layout.ns_per_count) {
      throw InputError(source, line.number, layout[Slot::kTime]->name,
                       fmt::format("{} is beyond the range of a time stamp",
                                   fields[layout[Slot::kTime]->index]));
    }
    row.time_ns = count * layout.ns_per_count;
  } else {
    r.time = value(Slot::kTime);
  }
  if (layout.geodetic) {
    row.geodetic = {value(Slot::kLat), bounded(Slot::kLon, 360.0, "deg"),
                    bounded(Slot::kAlt, kInsMaxAltitude, "m")};
    if (std::abs(row.geodetic.latitude_deg) > 90.0) {
      throw InputError(source, line.number, layout[Slot::kLat]->name,
                       fmt::format("latitude {} deg is outside [-90, 90]",
                                   format_number(row.geodetic.latitude_deg)));
    }
  } else {
    r.position_enu = {bounded(Slot::kX, kInsMaxPosition, "m"),
                      bounded(Slot::kY, kInsMaxPosition, "m"),
                      bounded(Slot::kZ, kInsMaxPosition, "m")};
  }
  if (layout[Slot::kVe]) {
    r.velocity_enu = {bounded(Slot::kVe, kInsMaxSpeed, "m/s"),
                      bounded(Slot::kVn, kInsMaxSpeed, "m/s"),
                      bounded(Slot::kVu, kInsMaxSpeed, "m/s")};
  }
  if (layout.quaternion) {
    const Eigen::Quaterniond q(value(Slot::kQw), value(Slot::kQx), value(Slot::kQy),
                               value(Slot::kQz));
    // A unit quaternion as written to 6 digits is within 1e-5 of norm 1; one far from it is not
    // an attitude (a column of something else, or a corrupt number).
    if (std::abs(q.norm() - 1.0) > 1e-2) {
      throw InputError(
          source, line.number, layout[Slot::kQw]->name,
          fmt::format("the attitude quaternion has norm {}, not 1", format_number(q.norm())));
    }
    r.attitude = euler_from_rotation(q.normalized().toRotationMatrix());
  } else {
    const double roll = angle(Slot::kRoll), pitch = angle(Slot::kPitch), yaw = angle(Slot::kYaw);
    r.attitude = {roll, pitch, layout.yaw_is_azimuth ? heading_enu_from_azimuth(yaw) : yaw};
  }
  if (layout[Slot::kStatus]) {
    r.status = parse_whole_number(fields[layout[Slot::kStatus]->index], where(Slot::kStatus));
  }
  return row;
}

// Positions into the tangent frame at the first row; velocity and attitude from the local-level
// axes at each row into that frame's axes.
GeodeticPosition to_local_enu(std::span<const ParsedRow> rows, std::vector<InsRecord>& records) {
  const LocalEnuFrame frame(rows.front().geodetic);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    InsRecord& r = records[i];
    const Eigen::Matrix3d frame_from_local_level = frame.frame_from_local_level(rows[i].geodetic);
    r.position_enu = frame.enu_from_geodetic(rows[i].geodetic);
    r.velocity_enu = frame_from_local_level * r.velocity_enu;
    r.attitude = euler_from_rotation(frame_from_local_level * rotation_from_euler(r.attitude));
  }
  return frame.origin();
}

std::string format_row(const InsRecord& r) {
  const Eigen::Vector3d& p = r.position_enu;
  const Eigen::Vector3d& v = r.velocity_enu;
  return format_numbers({r.time, p.x(), p.y(), p.z(), v.x(), v.y(), v.z(), r.attitude.roll,
                         r.attitude.pitch, r.attitude.yaw},
                        ",") +
         "\n";
}

}  // namespace

constexpr std::array<EnumName<YawConvention>, 2> kYawConventionNames{{
    {YawConvention::kEnu, "enu"},
    {YawConvention::kAzimuth, "azimuth"},
}};

constexpr std::array<EnumName<AngleUnit>, 2> kAngleUnitNames{{
    {AngleUnit::kRadians, "rad"},
    {AngleUnit::kDegrees, "deg"},
}};

const char* to_string(YawConvention convention) {
  return enum_to_string(kYawConventionNames, convention);
}

YawConvention yaw_convention_from_string(const std::string& text) {
  return enum_from_string(kYawConventionNames, text, "yaw convention");
}

std::vector<std::string> yaw_convention_names() { return enum_names(kYawConventionNames); }

const char* to_string(AngleUnit unit) { return enum_to_string(kAngleUnitNames, unit); }

AngleUnit angle_unit_from_string(const std::string& text) {
  return enum_from_string(kAngleUnitNames, text, "angle unit");
}

std::vector<std::string> angle_unit_names() { return enum_names(kAngleUnitNames); }

void InsCsvOptions::Check() const {
  // Enum values cast from a bad number (e.g. a binding's int) are named rather than misread.
  const OptionsCheck check("InsCsvOptions");
  check.that(!yaw_convention || *yaw_convention == YawConvention::kEnu ||
                 *yaw_convention == YawConvention::kAzimuth,
             "yaw_convention", "must be a YawConvention");
  check.that(angle_unit == AngleUnit::kRadians || angle_unit == AngleUnit::kDegrees, "angle_unit",
             "must be an AngleUnit");
  for (const auto& [quantity, header_name] : column_names) {
    if (!match_column(quantity, 0, *this)) {
      reject_argument(
          "InsCsvOptions.column_names: '{}' is not a column x2car reads (e.g. time, "
          "time_ns, east, lat, ve, roll_deg, heading, qw, status)",
          quantity);
    }
    if (header_name.empty()) {
      reject_argument("InsCsvOptions.column_names: '{}' maps to an empty name", quantity);
    }
  }
}

std::string format_ins_csv(std::span<const InsRecord> records) {
  std::string text(kInsCsvHeader);  // appended (GCC 12 false warning)
  text += '\n';
  for (const InsRecord& record : records) text += format_row(record);
  return text;
}

void write_ins_csv(const std::filesystem::path& path, std::span<const InsRecord> records) {
  write_text_file(path, format_ins_csv(records));
}

InsCsvLog read_ins_csv_log(const std::filesystem::path& path, const InsCsvOptions& options) {
  return parse_ins_csv_log(read_text_file(path), path.string(), options);
}

InsCsvLog parse_ins_csv_log(std::string_view text, const std::string& source_name,
                            const InsCsvOptions& options) {
  options.Check();
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) throw InputError(source_name, "empty file, expected a header line");
  const Layout layout = parse_header(lines.front(), options, source_name);
  if (lines.size() == 1) throw InputError(source_name, "no data rows after the header");
  std::vector<ParsedRow> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    rows.push_back(parse_row(lines[i], layout, source_name));
  }
  InsCsvLog log;
  std::vector<double> times;
  std::vector<std::size_t> numbers;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    InsRecord& record = log.records.emplace_back(rows[i].record);
    if (layout.time_ns) {
      record.time = seconds_between(rows[i].time_ns, rows.front().time_ns);
    }
    times.push_back(record.time);
    numbers.push_back(lines[i + 1].number);
  }
  if (layout.time_ns) {
    std::vector<double> unix_times;
    for (const ParsedRow& row : rows) unix_times.push_back(static_cast<double>(row.time_ns) / 1e9);
    check_one_clock(unix_times, numbers, source_name, layout[Slot::kTime]->name);
  }
  check_increasing_times(times, numbers, source_name, layout[Slot::kTime]->name);
  log.gaps = find_time_gaps(times, numbers);
  if (!layout.ignored.empty()) {
    log.notices.push_back(
        fmt::format("{}:{}: ignored column(s) {}: x2car does not read them "
                    "(docs/formats.md lists the names it reads)",
                    source_name, layout.header_line, join(layout.ignored)));
  }
  if (layout.time_ns) log.start_unix_time = static_cast<double>(rows.front().time_ns) / 1e9;
  if (layout.geodetic) log.enu_origin = to_local_enu(rows, log.records);
  return log;
}

std::vector<InsRecord> read_ins_csv(const std::filesystem::path& path,
                                    const InsCsvOptions& options) {
  return read_ins_csv_log(path, options).records;
}

std::vector<InsRecord> parse_ins_csv(std::string_view text, const std::string& source_name,
                                     const InsCsvOptions& options) {
  return parse_ins_csv_log(text, source_name, options).records;
}

std::vector<TimeGap> find_time_gaps(std::span<const double> times,
                                    std::span<const std::size_t> lines) {
  if (times.size() != lines.size()) {
    throw std::invalid_argument("find_time_gaps: times and lines differ in size");
  }
  if (times.size() < 2) return {};
  std::vector<double> steps(times.size() - 1);
  for (std::size_t i = 1; i < times.size(); ++i) steps[i - 1] = times[i] - times[i - 1];
  std::vector<double> sorted = steps;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double threshold = std::max(kTimeGapMinSeconds, kTimeGapStepFactor * *middle);
  std::vector<TimeGap> gaps;
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (steps[i - 1] > threshold) {
      gaps.push_back({i, lines[i - 1], lines[i], times[i - 1], times[i]});
    }
  }
  return gaps;
}

std::string time_gap_notice(const TimeGap& gap, const std::string& source_name) {
  return fmt::format(
      "{}:{}: the time jumps forward by {} s (from {} s on line {} to {} s): the log has a gap "
      "there (the device stopped, or two recordings were joined)",
      source_name, gap.line_after, format_number(gap.seconds()), format_number(gap.time_before),
      gap.line_before, format_number(gap.time_after));
}

void check_one_clock(std::span<const double> times, std::span<const std::size_t> lines,
                     const std::string& source_name, const std::string& field) {
  if (times.size() != lines.size()) {
    throw std::invalid_argument("check_one_clock: times and lines differ in size");
  }
  constexpr double kRelativeBelow = 1e7;  // [s]
  constexpr double kAbsoluteFrom = 1e8;   // [s]
  std::optional<std::size_t> previous;    // the last row whose clock is clear
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = std::abs(times[i]);
    if (t >= kRelativeBelow && t < kAbsoluteFrom) continue;
    if (previous && (std::abs(times[*previous]) < kRelativeBelow) != (t < kRelativeBelow)) {
      const auto kind = [](double time) {
        return std::abs(time) < kRelativeBelow ? "a relative time"
                                               : "an absolute (Unix or GPS) time";
      };
      throw InputError(
          source_name, lines[i], field,
          fmt::format("mixed clocks: {} s is {}, but {} s on line {} is {}; one log needs one "
                      "clock (were two logs joined, or did the device switch clocks?)",
                      format_number(times[i]), kind(times[i]), format_number(times[*previous]),
                      lines[*previous], kind(times[*previous])));
    }
    previous = i;
  }
}

void check_increasing_times(std::span<const double> times, std::span<const std::size_t> lines,
                            const std::string& source_name, const std::string& field) {
  if (times.size() != lines.size()) {
    throw std::invalid_argument("check_increasing_times: times and lines differ in size");
  }
  check_one_clock(times, lines, source_name, field);
  std::size_t repeated = 0;
  std::size_t backwards = 0;
  std::size_t first = 0;  // index of the first offending row; 0 = none (row 0 cannot offend)
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (times[i] > times[i - 1]) continue;
    (times[i] == times[i - 1] ? repeated : backwards) += 1;
    if (first == 0) first = i;
  }
  if (first == 0) return;
  throw InputError(
      source_name, lines[first], field,
      fmt::format("timestamps must strictly increase: {} row(s) repeat the previous time and {} "
                  "go back; the first is line {} ({} after {} on line {})",
                  repeated, backwards, lines[first], format_number(times[first]),
                  format_number(times[first - 1]), lines[first - 1]));
}

}  // namespace x2car::io
