#include "x2car/io/radar_delphi.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <cmath>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 15> kFields{
    "time_ns", "track_id", "x",           "y",        "vx",    "vy",         "status",    "bearing",
    "range",   "rcs",      "range_accel", "lat_rate", "width", "scan_index", "range_rate"};

enum Field : std::size_t {
  kTimeNs,
  kTrackId,
  kX,
  kY,
  kVx,
  kVy,
  kStatus,
  kBearing,
  kRange,
  kRcs,
  kRangeAccel,
  kLatRate,
  kWidth,
  kScanIndex,
  kRangeRate
};

bool is_header(const TextLine& line) {
  const std::string_view text = trim(line.text);
  return !text.empty() && std::isalpha(static_cast<unsigned char>(text.front())) != 0;
}

std::string format_row(const RadarDetection& d, std::int64_t unix_time_ns, std::size_t scan_index) {
  // Velocity across the line of sight: v . (-sin bearing, cos bearing).
  const double lateral_rate = -d.vx * std::sin(d.azimuth) + d.vy * std::cos(d.azimuth);
  return fmt::format(
      "{},{},{},{},{},{},{}\n", unix_time_ns,
      d.track_id == kNoTrackId ? std::string() : std::to_string(d.track_id),
      format_numbers({d.x, d.y, d.vx, d.vy}, ","),
      d.new_track ? kDelphiStatusNew : kDelphiStatusUpdated,
      format_numbers({d.azimuth, d.range, d.rcs_dbsm.value_or(0.0), 0.0, lateral_rate, 0.0}, ","),
      scan_index, format_number(d.range_rate));
}

// nullopt for a "no track" row (status 0 or 6), after every field is checked.
std::optional<StampedRadarDetection> parse_row(const TextLine& line, const std::string& source,
                                               AngleUnit bearing_unit) {
  const std::vector<std::string_view> f = split_exact_fields(line, kFields.size(), source);
  const auto where = [&](std::size_t i) { return FieldLocation{source, line.number, kFields[i]}; };
  std::array<double, kFields.size()> v{};
  for (const std::size_t i :
       {kX, kY, kVx, kVy, kBearing, kRange, kRcs, kRangeAccel, kLatRate, kWidth, kRangeRate}) {
    v[i] = parse_double(f[i], where(i));
  }
  StampedRadarDetection row;
  row.unix_time_ns = parse_integer(f[kTimeNs], where(kTimeNs));
  RadarDetection& d = row.detection;
  d.track_id = parse_radar_track_id(f[kTrackId], where(kTrackId), kDelphiMaxTrackId);
  const std::int64_t status = parse_integer(f[kStatus], where(kStatus));
  parse_integer(f[kScanIndex], where(kScanIndex));
  if (v[kRange] < 0.0) {
    throw InputError(source, line.number, kFields[kRange],
                     fmt::format("range must not be negative, found {}", f[kRange]));
  }
  for (const std::size_t i : {kX, kY, kRange}) {
    check_plausible(v[i], kRadarMaxRange, f[i], "m", where(i));
  }
  for (const std::size_t i : {kVx, kVy, kRangeRate}) {
    check_plausible(v[i], kRadarMaxSpeed, f[i], "m/s", where(i));
  }
  if (bearing_unit == AngleUnit::kDegrees) v[kBearing] = rad_from_deg(v[kBearing]);
  check_radar_azimuth(v[kBearing], f[kBearing], bearing_unit, where(kBearing));
  if (status == kDelphiStatusNoTrack || status == kDelphiStatusInvalidCoasted) return std::nullopt;
  d.new_track = status == kDelphiStatusNew;
  d.azimuth = v[kBearing];
  d.range = v[kRange];
  d.range_rate = v[kRangeRate];
  d.x = d.range * std::cos(d.azimuth);
  d.y = d.range * std::sin(d.azimuth);
  d.has_velocity = true;
  d.vx = v[kVx];
  d.vy = v[kVy];
  d.rcs_dbsm = v[kRcs];
  return row;
}

}  // namespace

std::span<const char* const> delphi_field_names() { return kFields; }

std::string format_delphi_scan(std::span<const RadarDetection> scan, std::int64_t unix_time_ns,
                               std::size_t scan_index) {
  std::string text;
  for (const RadarDetection& d : radar_scan_rows(scan, kDelphiMaxTrackId, "delphi")) {
    text += format_row(d, unix_time_ns, scan_index);
  }
  return text;
}

void write_delphi_radar(const std::filesystem::path& folder,
                        std::span<const RadarDetection> detections, double start_unix_time) {
  write_radar_scan_files(folder, detections, start_unix_time, format_delphi_scan);
}

std::vector<StampedRadarDetection> parse_delphi_scan(std::string_view text,
                                                     const std::string& source_name,
                                                     AngleUnit bearing_unit) {
  std::vector<TextLine> lines = split_lines(text);
  if (!lines.empty() && is_header(lines.front())) lines.erase(lines.begin());
  std::vector<StampedRadarDetection> rows;
  for (const TextLine& line : lines) {
    if (std::optional<StampedRadarDetection> row = parse_row(line, source_name, bearing_unit)) {
      rows.push_back(std::move(*row));
    }
  }
  return rows;
}

RadarLog read_delphi_radar(const std::filesystem::path& folder, AngleUnit bearing_unit) {
  std::vector<StampedRadarDetection> rows;
  for (const RadarScanFile& file : list_radar_scan_files(folder)) {
    std::vector<StampedRadarDetection> scan =
        parse_delphi_scan(read_text_file(file.path), file.path.string(), bearing_unit);
    rows.insert(rows.end(), scan.begin(), scan.end());
  }
  return make_radar_log(std::move(rows));
}

}  // namespace x2car::io
