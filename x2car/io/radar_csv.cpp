#include "x2car/io/radar_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_radar.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/radar_conti.hpp"
#include "x2car/io/radar_delphi.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::int64_t kNsPerMs = 1000000;
constexpr std::string_view kScanFileExtension = ".csv";

// Positions of the separators in "YYYY-MM-DD-HH-MM-SS-fff" and what they stand for in the
// "YYYY-MM-DD HH:MM:SS.fff" form that parse_utc_time reads.
constexpr std::size_t kScanNameLength = 23;
constexpr std::array<std::pair<std::size_t, char>, 6> kNameSeparators{
    {{4, '-'}, {7, '-'}, {10, ' '}, {13, ':'}, {16, ':'}, {19, '.'}}};

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}

// ---- generic CSV ----

struct GenericColumns {
  std::size_t count = 0;  // fields per row
  Delimiter delimiter = Delimiter::kAuto;
  AngleUnit azimuth_unit = AngleUnit::kRadians;
  std::vector<std::string> ignored;  // columns the reader does not use, "'name' (column)"
  std::map<std::string, std::size_t, std::less<>> index;
  bool has(std::string_view name) const { return index.find(name) != index.end(); }
  std::size_t at(std::string_view name) const { return index.find(name)->second; }
};

constexpr std::array<std::string_view, 10> kGenericColumns{
    "time", "track_id", "range", "azimuth", "range_rate", "x", "y", "vx", "vy", "rcs"};
constexpr std::array<std::string_view, 4> kGenericRequired{"time", "range", "azimuth",
                                                           "range_rate"};

GenericColumns parse_generic_header(const TextLine& line, const std::string& source) {
  GenericColumns columns;
  columns.delimiter = detect_delimiter(line.text);
  const std::vector<std::string_view> names = split_fields(line.text, columns.delimiter);
  columns.count = names.size();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!columns.index.emplace(std::string(names[i]), i).second) {
      throw InputError(source, line.number, std::string(names[i]), "duplicated column");
    }
    if (std::find(kGenericColumns.begin(), kGenericColumns.end(), names[i]) ==
        kGenericColumns.end()) {
      columns.ignored.push_back(fmt::format("{} ({})", quote_field(names[i]), i + 1));
    }
  }
  for (const std::string_view required : kGenericRequired) {
    if (!columns.has(required)) {
      throw InputError(source, line.number, std::string(required),
                       fmt::format("missing required column; the header must name time, range, "
                                   "azimuth and range_rate (the full header is '{}')",
                                   kRadarCsvHeader));
    }
  }
  for (const auto& [first, second] : {std::pair{"x", "y"}, std::pair{"vx", "vy"}}) {
    if (columns.has(first) != columns.has(second)) {
      throw InputError(source, line.number, columns.has(first) ? second : first,
                       fmt::format("columns {} and {} come together", first, second));
    }
  }
  return columns;
}

int parse_generic_track_id(std::string_view text, const FieldLocation& where) {
  if (text.empty()) return kNoTrackId;
  const std::int64_t id = parse_integer(text, where);
  if (id < 0 || id > 1000000000) {
    throw InputError(where.file, where.line, where.field,
                     fmt::format("track id must be a non-negative integer, found {}", id));
  }
  return static_cast<int>(id);
}

RadarDetection parse_generic_row(const TextLine& line, const GenericColumns& columns,
                                 const std::string& source) {
  const std::vector<std::string_view> f = split_exact_fields(
      line, columns.count, source, " (as many as the header names)", columns.delimiter);
  const auto where = [&](std::string_view name) {
    return FieldLocation{source, line.number, std::string(name)};
  };
  const auto number = [&](std::string_view name) {
    return parse_double(f[columns.at(name)], where(name));
  };
  RadarDetection d;
  d.time = number("time");
  d.range = number("range");
  if (d.range < 0.0) {
    throw InputError(source, line.number, "range",
                     fmt::format("range must not be negative, found {}", f[columns.at("range")]));
  }
  check_plausible(d.range, kRadarMaxRange, f[columns.at("range")], "m", where("range"));
  d.azimuth = number("azimuth");
  if (columns.azimuth_unit == AngleUnit::kDegrees) d.azimuth = rad_from_deg(d.azimuth);
  check_radar_azimuth(d.azimuth, f[columns.at("azimuth")], columns.azimuth_unit, where("azimuth"));
  d.range_rate = number("range_rate");
  check_plausible(d.range_rate, kRadarMaxSpeed, f[columns.at("range_rate")], "m/s",
                  where("range_rate"));
  if (columns.has("track_id")) {
    d.track_id = parse_generic_track_id(f[columns.at("track_id")], where("track_id"));
  }
  const auto bounded = [&](std::string_view name, double limit, const char* unit) {
    const double v = number(name);
    check_plausible(v, limit, f[columns.at(name)], unit, where(name));
    return v;
  };
  d.x = columns.has("x") ? bounded("x", kRadarMaxRange, "m") : d.range * std::cos(d.azimuth);
  d.y = columns.has("y") ? bounded("y", kRadarMaxRange, "m") : d.range * std::sin(d.azimuth);
  if (columns.has("vx")) {
    const bool vx_empty = f[columns.at("vx")].empty();
    if (vx_empty != f[columns.at("vy")].empty()) {
      throw InputError(source, line.number, vx_empty ? "vx" : "vy",
                       "vx and vy must both hold a number or both be empty");
    }
    if (!vx_empty) {
      d.has_velocity = true;
      d.vx = bounded("vx", kRadarMaxSpeed, "m/s");
      d.vy = bounded("vy", kRadarMaxSpeed, "m/s");
    }
  }
  if (columns.has("rcs") && !f[columns.at("rcs")].empty()) d.rcs_dbsm = number("rcs");
  return d;
}

std::string optional_number(bool present, double value) {
  return present ? format_number(value) : std::string();
}

std::string format_generic_row(const RadarDetection& d) {
  return fmt::format("{},{},{},{},{},{}\n", format_number(d.time),
                     d.track_id == kNoTrackId ? std::string() : std::to_string(d.track_id),
                     format_numbers({d.range, d.azimuth, d.range_rate, d.x, d.y}, ","),
                     optional_number(d.has_velocity, d.vx), optional_number(d.has_velocity, d.vy),
                     optional_number(d.rcs_dbsm.has_value(), d.rcs_dbsm.value_or(0.0)));
}

// Whether the first line of `path` is a generic radar CSV header (names the required columns).
bool has_generic_header(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line;
  if (!file || !std::getline(file, line)) return false;
  if (line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);  // UTF-8 byte order mark
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string_view> names = split_fields(line, detect_delimiter(line));
  return std::all_of(kGenericRequired.begin(), kGenericRequired.end(), [&](std::string_view name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  });
}

// The .csv files of `folder` whose first line is a generic radar CSV header, sorted.
std::vector<std::filesystem::path> generic_csv_files(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".csv" &&
        has_generic_header(entry.path())) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The generic CSV a radar folder holds: detections.csv, else its only .csv file with a generic
// header. InputError naming the folder otherwise.
std::filesystem::path generic_csv_in_folder(const std::filesystem::path& folder) {
  std::error_code error;
  if (std::filesystem::exists(folder / kRadarCsvFileName, error)) return folder / kRadarCsvFileName;
  const std::vector<std::filesystem::path> files = generic_csv_files(folder);
  if (files.size() == 1) return files.front();
  if (files.empty()) {
    throw InputError(folder.string(),
                     fmt::format("no {} (the generic layout's file) in the folder, nor a CSV file "
                                 "whose header names time, range, azimuth and range_rate",
                                 kRadarCsvFileName));
  }
  std::vector<std::string> names;
  for (const auto& file : files) names.push_back(file.filename().string());
  throw InputError(folder.string(),
                   fmt::format("holds {} CSV files with a generic radar header ({}); name the one "
                               "to read {} or pass it as --input",
                               files.size(), join(names), kRadarCsvFileName));
}

RadarLog read_radar_layout(const std::filesystem::path& input, RadarLayout layout,
                           const RadarReadOptions& options) {
  const AngleUnit angle_unit = options.angle_unit;
  switch (layout) {
    case RadarLayout::kBag:
      return read_radar_bag(input,
                            {.topic = options.topic, .allow_truncated = options.allow_truncated});
    case RadarLayout::kConti:
      return read_conti_radar(input);
    case RadarLayout::kDelphi:
      return read_delphi_radar(input, angle_unit);
    case RadarLayout::kGeneric: {
      std::error_code error;
      const bool folder = std::filesystem::is_directory(input, error);
      return read_radar_csv(folder ? generic_csv_in_folder(input) : input, angle_unit);
    }
  }
  throw std::invalid_argument("unknown radar layout");
}

// `error` from reading `input` as `layout`, with a hint when the files look like another layout.
InputError with_layout_hint(const InputError& error, const std::filesystem::path& input,
                            RadarLayout layout) {
  RadarLayout looks_like = layout;
  try {
    looks_like = detect_radar_layout(input);
  } catch (const std::exception&) {
    return error;  // no better guess
  }
  if (looks_like == layout) return error;
  // what() is the location, then ": ", then the message; the location alone is what an empty
  // message gives.
  const std::string_view what = error.what();
  const std::size_t location =
      std::string_view(InputError(error.file(), error.line(), error.field(), "").what()).size();
  return InputError(
      error.file(), error.line(), error.field(),
      fmt::format("{}; the files look like the {} layout: pass --layout {} (or "
                  "auto)",
                  what.substr(location), to_string(looks_like), to_string(looks_like)));
}

}  // namespace

void check_radar_azimuth(double azimuth, std::string_view text, AngleUnit unit,
                         const FieldLocation& where) {
  constexpr double kMargin = 1e-9;  // [rad] rounding of a value written at +-pi
  if (std::abs(azimuth) <= kPi + kMargin) return;
  throw InputError(where.file, where.line, where.field,
                   unit == AngleUnit::kRadians
                       ? fmt::format("{} is beyond +-pi, so not an azimuth in radians; if the "
                                     "layout holds degrees, pass --angle-unit deg",
                                     text)
                       : fmt::format("{} deg is beyond +-180 deg", text));
}

constexpr std::array<EnumName<RadarLayout>, 4> kRadarLayoutNames{{
    {RadarLayout::kConti, "conti"},
    {RadarLayout::kDelphi, "delphi"},
    {RadarLayout::kGeneric, "generic"},
    {RadarLayout::kBag, "bag"},
}};

std::string to_string(RadarLayout layout) { return enum_to_string(kRadarLayoutNames, layout); }

RadarLayout radar_layout_from_string(std::string_view name) {
  return enum_from_string(kRadarLayoutNames, name, "radar layout");
}

std::vector<std::string> radar_layout_names() { return enum_names(kRadarLayoutNames); }

std::string radar_scan_file_name(std::int64_t unix_time_ns) {
  const std::int64_t ms_ns = floor_div(unix_time_ns, kNsPerMs) * kNsPerMs;
  std::string name = format_utc_time(ms_ns).substr(0, kScanNameLength);
  for (const auto& separator : kNameSeparators) name[separator.first] = '-';
  return name + std::string(kScanFileExtension);
}

std::optional<std::int64_t> parse_radar_scan_file_name(std::string_view file_name) {
  if (!file_name.ends_with(kScanFileExtension)) return std::nullopt;
  file_name.remove_suffix(kScanFileExtension.size());
  if (file_name.size() != kScanNameLength) return std::nullopt;
  std::string text(file_name);
  for (const auto& [position, separator] : kNameSeparators) {
    if (text[position] != '-') return std::nullopt;
    text[position] = separator;
  }
  return parse_utc_time(text);
}

std::int64_t radar_unix_time_ns(double start_unix_time, double time) {
  if (!std::isfinite(start_unix_time) || !std::isfinite(time)) {
    throw std::invalid_argument("radar time or start time is not finite");
  }
  return std::llround(start_unix_time * 1e9) + std::llround(time * 1e9);
}

std::vector<std::span<const RadarDetection>> split_radar_scans(
    std::span<const RadarDetection> detections) {
  std::vector<std::span<const RadarDetection>> scans;
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= detections.size(); ++i) {
    if (i == detections.size() || detections[i].time != detections[begin].time) {
      scans.push_back(detections.subspan(begin, i - begin));
      begin = i;
    }
  }
  return scans;
}

std::vector<RadarScanFile> list_radar_scan_files(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) {
    throw InputError(folder.string(), "is not a folder; expected a folder of radar scan files");
  }
  std::vector<RadarScanFile> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().extension().string() != kScanFileExtension)
      continue;
    const std::string name = entry.path().filename().string();
    const std::optional<std::int64_t> ns = parse_radar_scan_file_name(name);
    if (!ns) {
      throw InputError(entry.path().string(),
                       "file name is not a scan time 'YYYY-MM-DD-HH-MM-SS-fff.csv' (UTC)");
    }
    files.push_back({entry.path(), *ns});
  }
  if (files.empty()) throw InputError(folder.string(), "no radar scan files (*.csv) in the folder");
  std::sort(files.begin(), files.end(), [](const RadarScanFile& a, const RadarScanFile& b) {
    return a.name_time_ns != b.name_time_ns ? a.name_time_ns < b.name_time_ns : a.path < b.path;
  });
  return files;
}

RadarLog make_radar_log(std::vector<StampedRadarDetection> rows) {
  std::stable_sort(rows.begin(), rows.end(),
                   [](const StampedRadarDetection& a, const StampedRadarDetection& b) {
                     return a.unix_time_ns < b.unix_time_ns;
                   });
  RadarLog log;
  if (rows.empty()) return log;
  const std::int64_t first_ns = rows.front().unix_time_ns;
  log.start_unix_time = static_cast<double>(first_ns) / 1e9;
  log.detections.reserve(rows.size());
  for (StampedRadarDetection& row : rows) {
    row.detection.time = seconds_between(row.unix_time_ns, first_ns);
    log.detections.push_back(std::move(row.detection));
  }
  return log;
}

std::vector<RadarDetection> radar_scan_rows(std::span<const RadarDetection> scan, int max_track_id,
                                            std::string_view layout) {
  std::vector<RadarDetection> rows(scan.begin(), scan.end());
  std::stable_sort(rows.begin(), rows.end(), [](const RadarDetection& a, const RadarDetection& b) {
    return a.track_id < b.track_id;
  });
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const RadarDetection& row = rows[i];
    if (row.track_id == kNoTrackId) {  // a cluster: no id, nothing to repeat
    } else if (row.track_id < 0 || row.track_id > max_track_id) {
      throw std::invalid_argument(
          fmt::format("{} radar: track id {} is outside 0-{}", layout, row.track_id, max_track_id));
    }
    if (i > 0 && row.track_id != kNoTrackId && rows[i - 1].track_id == row.track_id) {
      throw std::invalid_argument(
          fmt::format("{} radar: track id {} twice in one scan", layout, row.track_id));
    }
    if (!row.has_velocity) {
      throw std::invalid_argument(
          fmt::format("{} radar: track {} has no velocity", layout, row.track_id));
    }
  }
  return rows;
}

int parse_radar_track_id(std::string_view text, const FieldLocation& where, int max_track_id) {
  if (trim(text).empty()) return kNoTrackId;  // a cluster list's row
  const std::int64_t id = parse_integer(text, where);
  if (id < 0 || id > max_track_id) {
    throw InputError(where.file, where.line, where.field,
                     fmt::format("track id {} is outside 0-{}", id, max_track_id));
  }
  return static_cast<int>(id);
}

void write_radar_scan_files(const std::filesystem::path& folder,
                            std::span<const RadarDetection> detections, double start_unix_time,
                            const RadarScanFormatter& format_scan) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder.string(), "cannot create the folder: " + error.message());
  std::set<std::string> names;
  const std::vector<std::span<const RadarDetection>> scans = split_radar_scans(detections);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const std::int64_t first_ns = radar_unix_time_ns(start_unix_time, scans[i].front().time);
    const std::string name = radar_scan_file_name(first_ns);
    if (!names.insert(name).second) {
      throw std::invalid_argument("two radar scans less than 1 ms apart share the file name " +
                                  name);
    }
    write_text_file(folder / name, format_scan(scans[i], first_ns, i));
  }
}

std::string format_radar_csv(std::span<const RadarDetection> detections) {
  std::string text(kRadarCsvHeader);  // appended (GCC 12 false warning)
  text += '\n';
  for (const RadarDetection& detection : detections) text += format_generic_row(detection);
  return text;
}

void write_radar_csv(const std::filesystem::path& path,
                     std::span<const RadarDetection> detections) {
  write_text_file(path, format_radar_csv(detections));
}

RadarLog read_radar_csv(const std::filesystem::path& path, AngleUnit azimuth_unit) {
  return parse_radar_csv(read_text_file(path), path.string(), azimuth_unit);
}

RadarLog parse_radar_csv(std::string_view text, const std::string& source_name,
                         AngleUnit azimuth_unit) {
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) throw InputError(source_name, "empty file, expected a header line");
  GenericColumns columns = parse_generic_header(lines.front(), source_name);
  columns.azimuth_unit = azimuth_unit;
  if (lines.size() == 1) throw InputError(source_name, "no data rows after the header");
  RadarLog log;
  std::vector<double> times;
  std::vector<std::size_t> numbers;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    log.detections.push_back(parse_generic_row(lines[i], columns, source_name));
    times.push_back(log.detections.back().time);
    numbers.push_back(lines[i].number);
  }
  check_one_clock(times, numbers, source_name, "time");
  if (!columns.ignored.empty()) {
    log.notices.push_back(fmt::format("{}:{}: ignored column(s) {}: x2car does not read them",
                                      source_name, lines.front().number, join(columns.ignored)));
  }
  std::stable_sort(
      log.detections.begin(), log.detections.end(),
      [](const RadarDetection& a, const RadarDetection& b) { return a.time < b.time; });
  return log;
}

void write_radar(const std::filesystem::path& folder, RadarLayout layout,
                 std::span<const RadarDetection> detections, double start_unix_time) {
  switch (layout) {
    case RadarLayout::kConti:
      return write_conti_radar(folder, detections, start_unix_time);
    case RadarLayout::kDelphi:
      return write_delphi_radar(folder, detections, start_unix_time);
    case RadarLayout::kGeneric: {
      std::error_code error;
      std::filesystem::create_directories(folder, error);
      if (error) throw InputError(folder.string(), "cannot create the folder: " + error.message());
      return write_radar_csv(folder / kRadarCsvFileName, detections);
    }
    case RadarLayout::kBag:
      throw std::invalid_argument("write_radar: x2car does not write bags");
  }
  throw std::invalid_argument("unknown radar layout");
}

RadarLog read_radar(const std::filesystem::path& input, RadarLayout layout) {
  RadarReadOptions options;
  options.layout = layout;
  return read_radar(input, options);
}

RadarLayout detect_radar_layout(const std::filesystem::path& input) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::exists(input, error)) throw InputError(input.string(), "no such file or folder");
  if (bag_container_of(input)) return RadarLayout::kBag;
  if (!fs::is_directory(input, error) || fs::exists(input / kRadarCsvFileName, error)) {
    return RadarLayout::kGeneric;
  }
  // A folder of generic CSVs under other names: found by the header (one), or named (several).
  if (!generic_csv_files(input).empty()) {
    generic_csv_in_folder(input);  // throws unless there is exactly one
    return RadarLayout::kGeneric;
  }
  const RadarScanFile first = list_radar_scan_files(input).front();
  const std::string text = read_text_file(first.path);
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) {
    throw InputError(first.path.string(),
                     "cannot tell the radar layout: the first scan file is empty; pass --layout");
  }
  const std::vector<std::string_view> fields = split_fields(lines.front().text);
  if (fields.size() >= 3 && fields[0] == "time_ns" && fields[1] == "track_id" &&
      fields[2] == "vx") {
    return RadarLayout::kConti;
  }
  if (fields.size() == delphi_field_names().size()) return RadarLayout::kDelphi;
  throw InputError(first.path.string(), lines.front().number, {},
                   fmt::format("cannot tell the radar layout: the first line has {} fields; conti "
                               "files start with the header '{}', delphi rows have 15 fields, and "
                               "a generic folder holds {} (docs/formats.md); pass --layout",
                               fields.size(), kContiHeader, kRadarCsvFileName));
}

void RadarReadOptions::Check() const {
  // Enum values cast from a bad number (e.g. a binding's int) are named rather than misread.
  const OptionsCheck check("RadarReadOptions");
  check.that(!layout || *layout == RadarLayout::kConti || *layout == RadarLayout::kDelphi ||
                 *layout == RadarLayout::kGeneric || *layout == RadarLayout::kBag,
             "layout", "must be a RadarLayout");
  check.that(angle_unit == AngleUnit::kRadians || angle_unit == AngleUnit::kDegrees, "angle_unit",
             "must be an AngleUnit");
}

RadarLog read_radar(const std::filesystem::path& input, const RadarReadOptions& options) {
  options.Check();
  const RadarLayout layout = options.layout ? *options.layout : detect_radar_layout(input);
  try {
    RadarLog log = read_radar_layout(input, layout, options);
    log.layout = layout;
    return log;
  } catch (const InputError& error) {
    if (!options.layout) throw;
    throw with_layout_hint(error, input, layout);
  }
}

void set_polar_from_cartesian(RadarDetection& d) {
  d.range = std::hypot(d.x, d.y);
  d.azimuth = std::atan2(d.y, d.x);
  d.range_rate = d.range > 0.0 ? (d.x * d.vx + d.y * d.vy) / d.range : 0.0;
}

}  // namespace x2car::io
