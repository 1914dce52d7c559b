// The reference's Conti (ARS408-style object list) radar layout (Simulator issue; docs/formats.md):
// a folder with one CSV file per scan, named `YYYY-MM-DD-HH-MM-SS-fff.csv` after the UTC time of
// its first row (radar_csv.hpp), one header line, one tracked object per row, rows of a scan in
// ascending track id:
//
//   f0 time_ns     UTC time of the scan [integer ns since the Unix epoch]
//   f1 track_id    object id, 0-99 (ids are re-used after a track ends); empty in a cluster list
//                  (no tracking: io::kNoTrackId)
//   f2 vx  f3 vy   velocity relative to the radar, in the radar frame (x forward, y left) [m/s]
//   f4 px  f5 py   position in the radar frame [m]
//   f6 rcs         radar cross-section [dBsm] (empty: unknown)
//   f7 meas_state  ARS408 Object_MeasState: 1 new, 2 measured (others read as "not new")
//
// The reader needs the first six columns by these names, in this order; rcs and meas_state are
// optional and found by name, other columns are ignored. It derives range, azimuth and range rate
// from px, py, vx, vy (radar_csv.hpp).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/radar_csv.hpp"

namespace x2car::io {

constexpr std::string_view kContiHeader = "time_ns,track_id,vx,vy,px,py,rcs,meas_state";
constexpr int kContiMaxTrackId = 99;
constexpr int kContiMeasStateNew = 1;
constexpr int kContiMeasStateMeasured = 2;

// One scan file's text; the rows sorted by track id, stamped `unix_time_ns`. Throws
// std::invalid_argument for a track id outside 0-99, a repeated id, or a detection without
// velocity.
std::string format_conti_scan(std::span<const RadarDetection> scan, std::int64_t unix_time_ns);

// One scan per file (write_radar_scan_files). Throws as format_conti_scan and
// write_radar_scan_files do.
void write_conti_radar(const std::filesystem::path& folder,
                       std::span<const RadarDetection> detections, double start_unix_time);

// Throws InputError naming file, line and field for: a header that does not start with
// time_ns,track_id,vx,vy,px,py; a row whose field count differs from the header's; a non-integer
// time or track id; a track id outside 0-99 or not ascending within a scan (empty ids: clusters); a
// non-numeric or non-finite number. An empty file (not even a header) is an error; a header without
// rows is an empty scan.
std::vector<StampedRadarDetection> parse_conti_scan(std::string_view text,
                                                    const std::string& source_name);

// Every scan file of the folder (list_radar_scan_files), as one log.
RadarLog read_conti_radar(const std::filesystem::path& folder);

}  // namespace x2car::io
