// The reference layout `novatel_enu.csv` (Simulator issue; docs/formats.md): comma-separated, one
// header line whose first field is `gps_time`, then 12 fields per row:
//
//   f0  gps_time             UTC date-time "YYYY-MM-DD HH:MM:SS.ffffff"
//   f1  gps_seconds_of_week  GPS time of week [s] (GPS = UTC + 18 s, weeks from 1980-01-06)
//   f2  x_east  f3 y_north  f4 z_up       device position in a local ENU frame [m]
//   f5  v_north f6 v_east   f7 v_up       device velocity [m/s] (north first)
//   f8  roll    f9 pitch                  ZYX roll and pitch of world_from_ins in ENU [rad], i.e.
//                                         world_from_ins = Rz(yaw_enu) Ry(pitch) Rx(roll)
//   f10 azimuth                           heading clockwise from north [rad];
//                                         yaw_enu = pi/2 - azimuth (converted at the reader)
//   f11 status                            integer solution status (the simulator writes NMEA GGA
//                                         fix quality: 4 RTK fixed, 1 single point)
//
// Times are handled as integer nanoseconds since the Unix epoch (UTC, no time zone, no leap-second
// table: the GPS-UTC offset is fixed at 18 s, valid since 2017-01-01).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/ins_csv.hpp"

namespace x2car::io {

// 2026-06-01T10:00:00Z in Unix seconds: where the simulator's time 0 lands by default.
constexpr double kDefaultStartUnixTime = 1780308000.0;

// Seconds between the Unix epoch and the GPS epoch (1980-01-06T00:00:00Z), and GPS - UTC [s].
constexpr std::int64_t kGpsEpochUnixSeconds = 315964800;
constexpr std::int64_t kGpsMinusUtcSeconds = 18;

// The field names the writer puts in the header and the reader's errors use.
std::span<const char* const> novatel_field_names();

// "YYYY-MM-DD HH:MM:SS.ffffff" of a UTC instant [ns since the Unix epoch], rounded to the
// microsecond; proleptic Gregorian calendar by days-from-civil arithmetic.
std::string format_utc_time(std::int64_t unix_time_ns);

// The instant [ns since the Unix epoch] of "YYYY-MM-DD HH:MM:SS[.f...]" (UTC; 'T' or 't' may
// separate date and time; 1 to 9 fraction digits; "Z", "z", "+00:00", "+0000" or "+00" may
// follow; a leap second's :60 does not parse); nullopt when the
// text is not such a valid date-time or lies outside what an int64 of nanoseconds holds (1677-09-21
// to 2262-04-11).
std::optional<std::int64_t> parse_utc_time(std::string_view text);

// (later_ns - earlier_ns) / 1e9 [s], exact to the nanosecond when the difference fits an int64 and
// without a signed overflow when it does not (stamps read from a file may be any int64).
double seconds_between(std::int64_t later_ns, std::int64_t earlier_ns);

// GPS seconds of week [s] of a UTC instant: (unix - GPS epoch + 18 s) mod 604800.
double gps_seconds_of_week(std::int64_t unix_time_ns);

struct NovatelLog {
  double start_unix_time = 0.0;    // UTC of the first row [s since the Unix epoch]
  std::vector<InsRecord> records;  // times [s] relative to the first row; yaw in ENU
  std::vector<TimeGap> gaps;       // forward jumps in the times (find_time_gaps)
};

// Row i is stamped start_unix_time + records[i].time (rounded to the microsecond); positions and
// angles are written shortest-round-trip. Throws std::invalid_argument when start_unix_time or a
// record's time is not finite.
std::string format_novatel_enu(std::span<const InsRecord> records,
                               double start_unix_time = kDefaultStartUnixTime);
void write_novatel_enu(const std::filesystem::path& path, std::span<const InsRecord> records,
                       double start_unix_time = kDefaultStartUnixTime);

// Throws InputError naming file, line and field for: a missing header, a wrong field count, a
// non-numeric or non-finite number, an unparsable date-time, a non-integer status, no data rows,
// and timestamps that repeat or go back (how many, and the first line).
NovatelLog read_novatel_enu(const std::filesystem::path& path);
NovatelLog parse_novatel_enu(std::string_view text, const std::string& source_name);

}  // namespace x2car::io
