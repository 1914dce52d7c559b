// Reading a GNSS/INS log in any of the forms x2car accepts, with the form detected from the path:
//   - a KITTI raw OXTS folder (io/oxts.hpp): any directory (a drive folder holding `oxts/`, or
//     the `oxts` folder itself with `data/` + `timestamps.txt`);
//   - the reference layout `novatel_enu.csv` (io/novatel_csv.hpp): a file whose first line that
//     is neither blank nor a '#' comment has `gps_time` as its first comma-separated field;
//   - the generic CSV with a header (io/ins_csv.hpp): any other file.
// Every reader returns records in x2car's conventions (DESIGN §1): ENU positions in a local tangent
// frame, ENU velocities, world_from_ins as ZYX roll, pitch and yaw counter-clockwise from east.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/io/geodetic.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::io {

enum class InsFormat { kAuto, kNovatel, kCsv, kOxts, kBag };

// "auto", "novatel", "csv", "oxts", "bag" (MCAP, ROS 1 or ROS 2: bag.hpp); parsing throws
// std::invalid_argument listing the names.
const char* to_string(InsFormat format);
InsFormat ins_format_from_string(const std::string& text);
std::vector<std::string> ins_format_names();

struct InsReadOptions {
  InsFormat format = InsFormat::kAuto;
  InsCsvOptions csv;  // how the generic CSV's columns are read
  // A bag's pose or NavSatFix topic, and the Imu topic beside a NavSatFix one (bag_ins.hpp);
  // unset: its only one.
  std::optional<std::string> topic;
  std::optional<std::string> imu_topic;
};

struct InsLog {
  InsFormat format = InsFormat::kAuto;  // the form that was read (never kAuto)
  // UTC of the first record [s since the Unix epoch] when the log carries absolute times.
  std::optional<double> start_unix_time;
  // The geodetic origin of position_enu when the log has geodetic positions (OXTS; a generic CSV
  // with lat/lon/alt): the first record's position.
  std::optional<GeodeticPosition> enu_origin;
  std::vector<InsRecord> records;  // times [s], strictly increasing
  // Forward jumps in the times far beyond the log's rhythm (find_time_gaps): where a calibrator
  // should split the track. Lines are of the log file (OXTS: of timestamps.txt).
  std::vector<TimeGap> gaps;
  // What the CLI should print as warnings, each naming the file and line: every time gap and the
  // generic CSV's ignored header columns.
  std::vector<std::string> notices;
  // The device's frame: a bag's Odometry child_frame_id or Imu frame_id; empty for files.
  std::string frame_id;
};

// The form of `path` as kAuto would read it (reads only the file's first line with content).
// Throws InputError when the path does not exist or cannot be read.
InsFormat detect_ins_format(const std::filesystem::path& path);

// Reads `path` in options.format, or in the detected one for kAuto. Throws InputError naming the
// file, line and field on a missing path and on any malformed input (see each reader).
InsLog read_ins_log(const std::filesystem::path& path, const InsReadOptions& options = {});

}  // namespace x2car::io
