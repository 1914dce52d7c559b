// The reference's Delphi (ESR-style) radar layout (Simulator issue; docs/formats.md): a folder with
// one CSV file per scan, named `YYYY-MM-DD-HH-MM-SS-fff.csv` after the UTC time of its first row
// (radar_csv.hpp), no header, 15 comma-separated fields per row, one track per row:
//
//   f0  time_ns      UTC time of the scan [integer ns since the Unix epoch]
//   f1  track_id     0-63; empty in a cluster list (no tracking: io::kNoTrackId)
//   f2  x   f3 y     position in the radar frame (x forward, y left) [m]
//   f4  vx  f5 vy    velocity relative to the radar, in the radar frame [m/s]
//   f6  status       0 or 6: no track (the row is skipped); 1: new track; other: continuing
//                    (the writer uses 3, ESR "updated")
//   f7  bearing      azimuth, counter-clockwise positive [rad]
//   f8  range        [m], >= 0
//   f9  rcs          radar cross-section [dBsm]
//   f10 range_accel  [m/s^2] (written 0: not modelled)
//   f11 lat_rate     velocity across the line of sight, counter-clockwise positive [m/s]
//   f12 width        [m] (written 0: not modelled)
//   f13 scan_index   0-based count of scans in the log
//   f14 range_rate   d range / dt, negative approaching [m/s]
//
// The reader takes range, azimuth and range rate from f8, f7 and f14, x and y from range and
// bearing, the velocity from f4 and f5. A first line whose first field starts with a letter is a
// header and skipped.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/radar_csv.hpp"

namespace x2car::io {

constexpr int kDelphiMaxTrackId = 63;
constexpr int kDelphiStatusNoTrack = 0;
constexpr int kDelphiStatusNew = 1;
constexpr int kDelphiStatusUpdated = 3;
constexpr int kDelphiStatusInvalidCoasted = 6;

// The field names the reader's errors use (15).
std::span<const char* const> delphi_field_names();

// One scan file's text, rows sorted by track id, stamped `unix_time_ns`, with `scan_index` in f13.
// Throws std::invalid_argument for a track id outside 0-63, a repeated id, or a detection without
// velocity.
std::string format_delphi_scan(std::span<const RadarDetection> scan, std::int64_t unix_time_ns,
                               std::size_t scan_index);

void write_delphi_radar(const std::filesystem::path& folder,
                        std::span<const RadarDetection> detections, double start_unix_time);

// Throws InputError naming file, line and field for: a field count other than 15, a non-integer
// time, track id, status or scan index, a track id outside 0-63, a non-numeric or non-finite
// number, a negative range, a bearing beyond +-pi rad (+-180 deg when `bearing_unit` is kDegrees).
// Rows with status 0 or 6 are skipped (after the checks).
std::vector<StampedRadarDetection> parse_delphi_scan(std::string_view text,
                                                     const std::string& source_name,
                                                     AngleUnit bearing_unit = AngleUnit::kRadians);

RadarLog read_delphi_radar(const std::filesystem::path& folder,
                           AngleUnit bearing_unit = AngleUnit::kRadians);

}  // namespace x2car::io
