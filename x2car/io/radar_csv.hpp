// A 2-D automotive radar's detections (tracked objects), and the layouts x2car reads and writes
// them in (docs/formats.md, "Radar"):
//
//   conti    a folder of scan files, one per scan (radar_conti.hpp)
//   delphi   a folder of scan files, one per scan (radar_delphi.hpp)
//   generic  one CSV with a header (below)
//   bag      a radar_msgs/RadarScan or RadarTracks topic of a bag (bag_radar.hpp; read only)
//
// The radar frame R is x forward, y left, z up (DESIGN §1). A 2-D radar measures in its x-y plane:
//   range      = hypot(x, y)                      [m]
//   azimuth    = atan2(y, x)                      [rad], counter-clockwise positive, 0 = boresight
//   range_rate = d range / dt = (x vx + y vy) / range   [m/s], NEGATIVE when the target approaches
// where (vx, vy) is the target's velocity relative to the radar, (v_target - v_radar) expressed in
// R. For a static target seen from a radar mounted at yaw psi on a car driving straight at speed
// v: range_rate = -v cos(azimuth + psi).
//
// Scan files are named `YYYY-MM-DD-HH-MM-SS-fff.csv` after the UTC time of their first row
// (milliseconds, rounded down); all times are handled as integer nanoseconds since the Unix epoch
// with calendar arithmetic that never looks at the machine's time zone.
//
// Generic CSV, one header line naming the columns, one detection per row:
//   time,track_id,range,azimuth,range_rate,x,y,vx,vy,rcs
// time [s] on the GNSS/INS log's clock; range, azimuth, range_rate required; track_id (integer
// >= 0, empty = none), x,y (both or neither; derived from range and azimuth when absent), vx,vy
// (both or neither; empty fields = unknown) and rcs [dBsm] optional. Columns may come in any
// order; columns with other names are ignored.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/ins_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {

constexpr int kNoTrackId = -1;

struct RadarDetection {
  double time = 0.0;          // [s] from the log's time 0 (RadarLog::start_unix_time)
  int track_id = kNoTrackId;  // the radar's object id; kNoTrackId when the layout has none
  bool new_track = false;     // the first scan of this track (Conti meas_state 1, Delphi status 1)
  double range = 0.0;         // hypot(x, y) [m]
  double azimuth = 0.0;       // atan2(y, x), counter-clockwise positive [rad]
  double range_rate = 0.0;    // d range / dt, negative approaching [m/s]
  double x = 0.0;             // position in the radar frame, forward [m]
  double y = 0.0;             // left [m]
  bool has_velocity = false;  // whether vx, vy hold a value
  double vx = 0.0;            // velocity relative to the radar, in the radar frame [m/s]
  double vy = 0.0;            // [m/s]
  std::optional<double> rcs_dbsm;  // radar cross-section [dBsm], when the layout has it
};

// kBag: a bag's radar_msgs topic (bag_radar.hpp); read only.
enum class RadarLayout { kConti, kDelphi, kGeneric, kBag };

struct RadarLog {
  // UTC of the log's time 0 [s since the Unix epoch]: the earliest row of a Conti or Delphi folder.
  // 0 for the generic CSV, whose times are already on the GNSS/INS log's clock.
  double start_unix_time = 0.0;
  std::vector<RadarDetection> detections;      // in time order (rows of equal time keep file order)
  RadarLayout layout = RadarLayout::kGeneric;  // the layout read (read_radar sets it)
  // What the CLI should print as warnings, each naming the file and line: header columns the
  // reader ignored.
  std::vector<std::string> notices;
  std::string frame_id;  // the sensor's frame (a bag's header.frame_id); empty for files
};

std::string to_string(RadarLayout layout);  // "conti", "delphi", "generic", "bag"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
RadarLayout radar_layout_from_string(std::string_view name);
std::vector<std::string> radar_layout_names();  // the CLI's choices, in table order

// ---- scan folders (Conti and Delphi) ------------------------------------------------------------

// "YYYY-MM-DD-HH-MM-SS-fff.csv" of a UTC instant [ns since the Unix epoch], milliseconds rounded
// down.
std::string radar_scan_file_name(std::int64_t unix_time_ns);
// The instant [ns] a scan file's name stands for; nullopt when it is not such a name.
std::optional<std::int64_t> parse_radar_scan_file_name(std::string_view file_name);

// The UTC instant [ns] of `time` [s] on a log that starts at `start_unix_time` [s]; both rounded
// to the nanosecond separately, as the GNSS/INS writer does, so the two logs share one clock.
std::int64_t radar_unix_time_ns(double start_unix_time, double time);

// Runs of equal time in `detections` (one radar scan each), in order.
std::vector<std::span<const RadarDetection>> split_radar_scans(
    std::span<const RadarDetection> detections);

struct RadarScanFile {
  std::filesystem::path path;
  std::int64_t name_time_ns = 0;  // what the name says [ns]
};

// The *.csv files of a scan folder, sorted by the time in their names (other files are ignored).
// Throws InputError for a missing folder, a folder without .csv files, and a .csv file whose name
// is not a scan time (naming it).
std::vector<RadarScanFile> list_radar_scan_files(const std::filesystem::path& folder);

// One row of a scan file with its absolute time, before the log's time 0 is known.
struct StampedRadarDetection {
  std::int64_t unix_time_ns = 0;  // [ns since the Unix epoch, UTC]
  RadarDetection detection;       // time still unset
};

// The log of rows from any number of scan files: time 0 is the earliest row, every detection's
// time is relative to it, and rows are sorted by time (rows of equal time keep their order).
// An empty input gives an empty log.
RadarLog make_radar_log(std::vector<StampedRadarDetection> rows);

// The scan's detections sorted by track id, for the scan-file writers (detections without a track
// id, kNoTrackId, first, in their order: a cluster list). Throws std::invalid_argument naming
// `layout` for an id outside 0..max_track_id, a repeated id, or a detection without velocity.
std::vector<RadarDetection> radar_scan_rows(std::span<const RadarDetection> scan, int max_track_id,
                                            std::string_view layout);

// A track id field: an integer in [0, max_track_id], or empty for none (kNoTrackId: a cluster
// list's row); InputError at `where` otherwise.
int parse_radar_track_id(std::string_view text, const FieldLocation& where, int max_track_id);

// Text of one scan file from its detections, the UTC instant of its first row [ns] and its
// 0-based position in the log.
using RadarScanFormatter = std::function<std::string(
    std::span<const RadarDetection> scan, std::int64_t first_unix_time_ns, std::size_t index)>;

// Creates `folder` and writes one file per scan (split_radar_scans; scans without detections get
// no file), named after the scan's first row. Throws std::invalid_argument when two scans would
// share a file name (less than 1 ms apart) or a time is not finite, InputError when the folder or
// a file cannot be written.
void write_radar_scan_files(const std::filesystem::path& folder,
                            std::span<const RadarDetection> detections, double start_unix_time,
                            const RadarScanFormatter& format_scan);

// ---- generic CSV
// ----------------------------------------------------------------------------------

constexpr std::string_view kRadarCsvHeader = "time,track_id,range,azimuth,range_rate,x,y,vx,vy,rcs";

// Writes every column of kRadarCsvHeader; unknown values (no track id, no velocity, no RCS) are
// empty fields. Numbers are shortest round-trip.
std::string format_radar_csv(std::span<const RadarDetection> detections);
void write_radar_csv(const std::filesystem::path& path, std::span<const RadarDetection> detections);

// A header separated by semicolons is read so (detect_delimiter). Throws InputError naming file,
// line and field for: no header, a missing required column, a duplicated column, x without y or vx
// without vy, a wrong field count, a non-numeric or non-finite number, a negative range, a value
// beyond the plausibility bounds (kRadarMaxRange, kRadarMaxSpeed), an
// azimuth beyond +-pi rad (+-180 deg with `azimuth_unit` kDegrees; the message suggests
// --angle-unit deg), mixed clocks (check_one_clock), a negative or non-integer track id, only one
// of vx and vy, no rows. Other columns are named in a notice.
RadarLog read_radar_csv(const std::filesystem::path& path,
                        AngleUnit azimuth_unit = AngleUnit::kRadians);
RadarLog parse_radar_csv(std::string_view text, const std::string& source_name,
                         AngleUnit azimuth_unit = AngleUnit::kRadians);

// Plausibility bounds of the radar readers: far beyond any automotive radar, close enough that a
// corrupt number (1e308) is caught at its line instead of overflowing a computation later.
constexpr double kRadarMaxRange = 1e4;  // [m] of a range or a position coordinate
constexpr double kRadarMaxSpeed = 1e3;  // [m/s] of a range rate or a velocity component

// Throws InputError unless `azimuth` [rad] lies within +-pi (a small rounding margin allowed): a
// larger value is most likely in degrees. `unit` is what the layout read it as; the message shows
// `text` as written and, for radians, suggests --angle-unit deg.
void check_radar_azimuth(double azimuth, std::string_view text, AngleUnit unit,
                         const FieldLocation& where);

// ---- any layout
// ----------------------------------------------------------------------------------

// The file the generic layout is written to inside a radar folder.
constexpr std::string_view kRadarCsvFileName = "detections.csv";

// conti and delphi: scan files in `folder`; generic: `folder`/detections.csv. `detections` times
// are relative to `start_unix_time` [s]; the generic CSV writes them as they are. Detections
// without a track id (kNoTrackId: a cluster list) are written with an empty id field in every
// layout.
void write_radar(const std::filesystem::path& folder, RadarLayout layout,
                 std::span<const RadarDetection> detections, double start_unix_time);
// Reads what write_radar writes; for the generic layout `input` may also be the CSV file itself,
// or a folder with one CSV under another name (detect_radar_layout).
// When the files do not read as `layout` but look like another layout (detect_radar_layout), the
// error says so ("the files look like the delphi layout: pass --layout delphi or auto").
RadarLog read_radar(const std::filesystem::path& input, RadarLayout layout);

// The layout of a radar input, from what is there: a file, or a folder holding detections.csv or
// exactly one .csv file whose header names time, range, azimuth and range_rate (another name for
// the generic CSV, which read_radar then reads), is generic; a folder of scan files
// (list_radar_scan_files) is conti when the first file's first line is a header starting
// time_ns,track_id,vx (radar_conti.hpp), delphi when it has 15 fields (radar_delphi.hpp). Throws
// InputError naming the path (and the scan file's line) otherwise, and for a folder of several
// generic CSVs (naming them).
RadarLayout detect_radar_layout(const std::filesystem::path& input);

struct RadarReadOptions {
  std::optional<RadarLayout> layout;  // unset (default): detect_radar_layout
  // Unit of the angles the layout writes as numbers: the generic CSV's azimuth and Delphi's
  // bearing (Conti has none: it derives the azimuth from px, py). Default radians
  // (docs/formats.md); some exports write degrees.
  AngleUnit angle_unit = AngleUnit::kRadians;
  // A bag's radar topic (unset: its only one), and whether an MCAP file cut short is read up to
  // the cut.
  std::optional<std::string> topic;
  bool allow_truncated = false;

  void Check() const;  // throws std::invalid_argument naming a field out of range
};

RadarLog read_radar(const std::filesystem::path& input, const RadarReadOptions& options);

// Fills range, azimuth and range_rate from x, y, vx, vy (range_rate 0 at range 0).
void set_polar_from_cartesian(RadarDetection& detection);

}  // namespace x2car::io
