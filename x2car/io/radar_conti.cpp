#include "x2car/io/radar_conti.hpp"

#include <fmt/format.h>

#include <array>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// The columns the reader needs, in this order, at the start of the header.
constexpr std::array<std::string_view, 6> kRequired{"time_ns", "track_id", "vx", "vy", "px", "py"};

struct ContiColumns {
  std::size_t count = 0;           // fields per row
  std::optional<std::size_t> rcs;  // index of the optional columns
  std::optional<std::size_t> meas_state;
  std::vector<std::string> ignored;  // other columns, "'name' (column)"
};

ContiColumns parse_header(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> names = split_fields(line.text);
  for (std::size_t i = 0; i < kRequired.size(); ++i) {
    if (i >= names.size() || names[i] != kRequired[i]) {
      const std::string found =
          i < names.size() ? "is " + quote_field(names[i]) : std::string("is missing");
      throw InputError(source, line.number, field_index(i),
                       fmt::format("expected a header starting with "
                                   "'time_ns,track_id,vx,vy,px,py': column {} {}, expected '{}'",
                                   i + 1, found, kRequired[i]));
    }
  }
  ContiColumns columns;
  columns.count = names.size();
  for (std::size_t i = kRequired.size(); i < names.size(); ++i) {
    if (names[i] == "rcs") {
      columns.rcs = i;
    } else if (names[i] == "meas_state") {
      columns.meas_state = i;
    } else {
      columns.ignored.push_back(fmt::format("{} ({})", quote_field(names[i]), i + 1));
    }
  }
  return columns;
}

StampedRadarDetection parse_row(const TextLine& line, const ContiColumns& columns,
                                const std::vector<std::string_view>& names,
                                const std::string& source) {
  const std::vector<std::string_view> f =
      split_exact_fields(line, columns.count, source, " (as many as the header names)");
  const auto where = [&](std::size_t i) {
    return FieldLocation{source, line.number, std::string(names[i])};
  };
  StampedRadarDetection row;
  row.unix_time_ns = parse_integer(f[0], where(0));
  RadarDetection& d = row.detection;
  d.track_id = parse_radar_track_id(f[1], where(1), kContiMaxTrackId);
  const auto bounded = [&](std::size_t i, double limit, const char* unit) {
    const double v = parse_double(f[i], where(i));
    check_plausible(v, limit, f[i], unit, where(i));
    return v;
  };
  d.has_velocity = true;
  d.vx = bounded(2, kRadarMaxSpeed, "m/s");
  d.vy = bounded(3, kRadarMaxSpeed, "m/s");
  d.x = bounded(4, kRadarMaxRange, "m");
  d.y = bounded(5, kRadarMaxRange, "m");
  set_polar_from_cartesian(d);
  if (columns.rcs && !f[*columns.rcs].empty())
    d.rcs_dbsm = parse_double(f[*columns.rcs], where(*columns.rcs));
  if (columns.meas_state) {
    d.new_track =
        parse_integer(f[*columns.meas_state], where(*columns.meas_state)) == kContiMeasStateNew;
  }
  return row;
}

}  // namespace

std::string format_conti_scan(std::span<const RadarDetection> scan, std::int64_t unix_time_ns) {
  std::string text(kContiHeader);  // appended (GCC 12 false warning)
  text += '\n';
  for (const RadarDetection& d : radar_scan_rows(scan, kContiMaxTrackId, "conti")) {
    text += fmt::format("{},{},{},{},{}\n", unix_time_ns,
                        d.track_id == kNoTrackId ? std::string() : std::to_string(d.track_id),
                        format_numbers({d.vx, d.vy, d.x, d.y}, ","),
                        d.rcs_dbsm ? format_number(*d.rcs_dbsm) : std::string(),
                        d.new_track ? kContiMeasStateNew : kContiMeasStateMeasured);
  }
  return text;
}

void write_conti_radar(const std::filesystem::path& folder,
                       std::span<const RadarDetection> detections, double start_unix_time) {
  write_radar_scan_files(folder, detections, start_unix_time,
                         [](std::span<const RadarDetection> scan, std::int64_t ns, std::size_t) {
                           return format_conti_scan(scan, ns);
                         });
}

namespace {

struct ContiScan {
  std::vector<StampedRadarDetection> rows;
  std::size_t header_line = 0;
  std::vector<std::string> ignored;  // header columns the reader does not use
};

ContiScan parse_scan(std::string_view text, const std::string& source_name) {
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) throw InputError(source_name, "empty file, expected a header line");
  const ContiColumns columns = parse_header(lines.front(), source_name);
  const std::vector<std::string_view> names = split_fields(lines.front().text);
  ContiScan scan{{}, lines.front().number, columns.ignored};
  std::vector<StampedRadarDetection>& rows = scan.rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    rows.push_back(parse_row(lines[i], columns, names, source_name));
    if (i == 1) continue;
    const StampedRadarDetection& previous = rows[rows.size() - 2];
    const int id = rows.back().detection.track_id;
    if (previous.unix_time_ns == rows.back().unix_time_ns && id != kNoTrackId &&
        previous.detection.track_id >= id) {
      throw InputError(source_name, lines[i].number, "track_id",
                       fmt::format("track ids of a scan must ascend: {} follows {}",
                                   rows.back().detection.track_id, previous.detection.track_id));
    }
  }
  return scan;
}

}  // namespace

std::vector<StampedRadarDetection> parse_conti_scan(std::string_view text,
                                                    const std::string& source_name) {
  return parse_scan(text, source_name).rows;
}

RadarLog read_conti_radar(const std::filesystem::path& folder) {
  std::vector<StampedRadarDetection> rows;
  std::optional<std::string> notice;  // about the first file with columns the reader ignores
  for (const RadarScanFile& file : list_radar_scan_files(folder)) {
    ContiScan scan = parse_scan(read_text_file(file.path), file.path.string());
    rows.insert(rows.end(), scan.rows.begin(), scan.rows.end());
    if (!notice && !scan.ignored.empty()) {
      notice = fmt::format("{}:{}: ignored column(s) {}: x2car does not read them",
                           file.path.string(), scan.header_line, join(scan.ignored));
    }
  }
  RadarLog log = make_radar_log(std::move(rows));
  if (notice) log.notices.push_back(*notice);
  return log;
}

}  // namespace x2car::io
