// One GNSS/INS log in x2car's conventions (DESIGN §1), and the generic CSV it is read from.
//
// The reader takes its columns from the header line (names case-insensitive, trimmed, in any
// order; unknown columns ignored). docs/formats.md lists them; in short:
//
//   time      `time` or `time_s` [s], or `time_ns` (integer ns since the Unix epoch)
//   position  ENU `x,y,z` (or `east,north,up`) [m], or geodetic `lat,lon,alt` (or
//             `latitude,longitude,altitude`) [deg, deg, m above WGS84], converted to a local ENU
//             tangent frame at the first row (io/geodetic.hpp)
//   velocity  optional: `vx,vy,vz` or `ve,vn,vu` or `v_east,v_north,v_up` [m/s] (ENU)
//   attitude  `roll`, `pitch` and `yaw` (ENU: counter-clockwise from east) or `heading`/`azimuth`
//             (clockwise from north) of world_from_ins = Rz(yaw) Ry(pitch) Rx(roll); radians, or
//             degrees when the name ends in `_deg` (`yaw_deg`)
//   status    optional integer solution status
//
// The writer produces `time,x,y,z,vx,vy,vz,roll,pitch,yaw` (kInsCsvHeader), which reads back
// exactly.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/io/angle_unit.hpp"
#include "x2car/io/geodetic.hpp"

namespace x2car::io {

// One sample of a GNSS/INS device, already in ENU and radians (readers convert azimuths).
struct InsRecord {
  double time = 0.0;                                       // [s] on the log's clock
  Eigen::Vector3d position_enu = Eigen::Vector3d::Zero();  // of the device [m]
  // Of the device [m/s]. All zero when the log has no velocity: the calibrator then differentiates
  // the smoothed track instead.
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();
  // world_from_ins as Rz(yaw) Ry(pitch) Rx(roll); yaw counter-clockwise from east [rad].
  EulerAngles attitude;
  // Solution status as the device reports it (the simulator writes NMEA GGA fix quality: 4 RTK
  // fixed, 5 RTK float, 2 differential, 1 single point; OXTS folders give their posmode); 0 when
  // the log has none.
  int status = 0;
};

// Plausibility bounds of the GNSS/INS readers (check_plausible): far beyond any drive.
constexpr double kInsMaxPosition = 1e8;  // [m] of an ENU coordinate (UTM northings are below 1e7)
constexpr double kInsMaxAltitude = 1e5;  // [m] above or below the WGS84 ellipsoid
constexpr double kInsMaxSpeed = 1e3;     // [m/s] of a velocity component (3600 km/h)
constexpr double kInsMaxAngle = 2.0 * kPi;  // [rad] of roll, pitch or yaw

// How a heading column counts its angle.
enum class YawConvention {
  kEnu,      // counter-clockwise from east (x2car's yaw; ROS, KITTI OXTS)
  kAzimuth,  // clockwise from north (NovAtel, OxTS NCOM, a compass); yaw_enu = pi/2 - azimuth
};

// "enu", "azimuth" and "rad", "deg" (one table each in ins_csv.cpp); parsing throws
// std::invalid_argument listing the names; ..._names() are the CLI's choices.
const char* to_string(YawConvention convention);
YawConvention yaw_convention_from_string(const std::string& text);
std::vector<std::string> yaw_convention_names();
const char* to_string(AngleUnit unit);
AngleUnit angle_unit_from_string(const std::string& text);
std::vector<std::string> angle_unit_names();

struct InsCsvOptions {
  // Convention of the heading column. Unset (default): the header names it — `yaw` is ENU,
  // `heading` and `azimuth` are clockwise from north. Set: applies to whichever of the three
  // names the file uses (for a file whose `yaw` is really an azimuth, or the reverse).
  std::optional<YawConvention> yaw_convention;
  // Unit of `roll`, `pitch` and the heading column when the name has no unit suffix. Default
  // radians; a `_deg` or `_rad` suffix always wins.
  AngleUnit angle_unit = AngleUnit::kRadians;
  // A vendor's header names, read as x2car's: {"time_ns": "gps_ns", "east": "E", ...}, each key a
  // column name the reader knows (with a `_deg`/`_rad` suffix where it takes one), each value a
  // column of the header (case-insensitive). Empty: the header's names are used as they are.
  std::map<std::string, std::string> column_names;

  // Throws std::invalid_argument on an enumerator out of range or a key the reader does not know.
  void Check() const;
};

// A forward jump in a log's time stamps far beyond its rhythm: the device stopped logging, or two
// recordings were joined. The records either side are kept; what to do with the gap (split the
// track there) is the calibrator's business, and a jump must not cost it time or memory in
// proportion to its length.
struct TimeGap {
  std::size_t record = 0;       // index of the first record after the gap
  std::size_t line_before = 0;  // 1-based line of the record before the gap
  std::size_t line_after = 0;   // 1-based line of the record after it (records[record])
  double time_before = 0.0;     // [s] time of the record before the gap
  double time_after = 0.0;      // [s] time of the record after it
  double seconds() const { return time_after - time_before; }
};

// A step between consecutive records is a gap when it exceeds both kTimeGapMinSeconds and
// kTimeGapStepFactor times the log's median step (a 100 Hz log: 5 s; a 1 Hz log: 50 s).
constexpr double kTimeGapMinSeconds = 5.0;
constexpr double kTimeGapStepFactor = 50.0;

// The gaps in `times` (strictly increasing; `lines` holds each time's 1-based line number).
std::vector<TimeGap> find_time_gaps(std::span<const double> times,
                                    std::span<const std::size_t> lines);
// "FILE:LINE: the time jumps forward by 604800 s (from 12.5 on line 1250 to 604812.5); ...": for
// the CLI to print as a warning.
std::string time_gap_notice(const TimeGap& gap, const std::string& source_name);

// A generic CSV as read, with what the file says about its clocks and frames.
struct InsCsvLog {
  // UTC of the first row [s since the Unix epoch] when the time column is `time_ns`; the records'
  // times are then seconds from the first row. Unset for `time`/`time_s` (times kept as written).
  std::optional<double> start_unix_time;
  // The first row's geodetic position when the file has lat/lon/alt: the origin of position_enu.
  // Velocities and attitudes, which a device reports in the local-level axes at its own position,
  // are turned into the origin's axes (LocalEnuFrame::frame_from_local_level).
  std::optional<GeodeticPosition> enu_origin;
  std::vector<InsRecord> records;  // times strictly increasing
  std::vector<TimeGap> gaps;       // forward jumps in the times (find_time_gaps)
  // What the CLI should print as warnings: header columns the reader ignored (each named).
  std::vector<std::string> notices;
};

// The header line the generic CSV starts with (without the line break).
constexpr std::string_view kInsCsvHeader = "time,x,y,z,vx,vy,vz,roll,pitch,yaw";

// Numbers are written shortest-round-trip, so the file reads back exactly (status is not written).
std::string format_ins_csv(std::span<const InsRecord> records);
void write_ins_csv(const std::filesystem::path& path, std::span<const InsRecord> records);

// Reads the generic CSV. '#' comment lines and blank lines are skipped. Throws InputError naming
// file, line and field for: missing required columns (saying which and what names are accepted),
// both ENU and geodetic positions, an incomplete velocity, two columns for one quantity, a wrong
// field count, a non-numeric or non-finite value, a latitude outside [-90, 90] deg, a non-integer
// status, no rows, and times that do not strictly increase (how many, and the first line).
InsCsvLog read_ins_csv_log(const std::filesystem::path& path, const InsCsvOptions& options = {});
InsCsvLog parse_ins_csv_log(std::string_view text, const std::string& source_name,
                            const InsCsvOptions& options = {});

// The records of read_ins_csv_log / parse_ins_csv_log.
std::vector<InsRecord> read_ins_csv(const std::filesystem::path& path,
                                    const InsCsvOptions& options = {});
std::vector<InsRecord> parse_ins_csv(std::string_view text, const std::string& source_name,
                                     const InsCsvOptions& options = {});

// Throws InputError when `times` mix two clocks: relative times (|t| below 1e7 s, about 4 months)
// and absolute ones (|t| from 1e8 s: Unix or GPS seconds), e.g. 12.3 then 1.7e9. The message names
// the line where the clock changes and the line before it. Shared by the INS readers.
void check_one_clock(std::span<const double> times, std::span<const std::size_t> lines,
                     const std::string& source_name, const std::string& field);

// Throws InputError (check_one_clock first) unless `times` strictly increase. The message says how
// many rows repeat the previous time and how many go back, and names the first offending line
// (`lines` holds each time's 1-based line number) and `field`. Shared by the INS readers.
void check_increasing_times(std::span<const double> times, std::span<const std::size_t> lines,
                            const std::string& source_name, const std::string& field);

}  // namespace x2car::io
