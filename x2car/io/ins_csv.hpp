// One GNSS/INS log in x2car's conventions (DESIGN §1), and its generic CSV form:
//
//   time,x,y,z,vx,vy,vz,roll,pitch,yaw
//
// time [s]; x y z: device position in a local ENU frame [m]; vx vy vz: device velocity in ENU
// [m/s]; roll pitch yaw: world_from_ins = Rz(yaw) Ry(pitch) Rx(roll) [rad], yaw counter-clockwise
// from east. One header line, comma-separated, one row per sample, times strictly increasing.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::io {

// One sample of a GNSS/INS device, already in ENU and radians (readers convert azimuths).
struct InsRecord {
  double time = 0.0;                                       // [s] on the log's clock
  Eigen::Vector3d position_enu = Eigen::Vector3d::Zero();  // of the device [m]
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();  // of the device [m/s]
  // world_from_ins as Rz(yaw) Ry(pitch) Rx(roll); yaw counter-clockwise from east [rad].
  EulerAngles attitude;
  // Solution status as the device reports it (the simulator writes NMEA GGA fix quality: 4 RTK
  // fixed, 5 RTK float, 2 differential, 1 single point); the generic CSV does not carry it.
  int status = 0;
};

// The header line the generic CSV starts with (without the line break).
constexpr std::string_view kInsCsvHeader = "time,x,y,z,vx,vy,vz,roll,pitch,yaw";

// Numbers are written shortest-round-trip, so the file reads back exactly.
std::string format_ins_csv(std::span<const InsRecord> records);
void write_ins_csv(const std::filesystem::path& path, std::span<const InsRecord> records);

// Reads a file whose first non-blank line is exactly kInsCsvHeader (the configurable reader
// comes with the GNSS/INS calibrator). Throws InputError naming file, line and field for a
// different header, a wrong field count, a non-numeric or non-finite value, no rows, and times
// that do not strictly increase. Status is 0.
std::vector<InsRecord> read_ins_csv(const std::filesystem::path& path);
std::vector<InsRecord> parse_ins_csv(std::string_view text, const std::string& source_name);

// Throws InputError unless `times` strictly increase. The message says how many rows repeat the
// previous time and how many go back, and names the first offending line (`lines` holds each
// time's 1-based line number) and `field`. Shared by the INS readers.
void check_increasing_times(std::span<const double> times, std::span<const std::size_t> lines,
                            const std::string& source_name, const std::string& field);

}  // namespace x2car::io
