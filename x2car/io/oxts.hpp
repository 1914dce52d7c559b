// KITTI raw OXTS folders (KITTI raw data devkit, readme.txt "oxts"):
//
//   <drive>/oxts/timestamps.txt     one "YYYY-MM-DD HH:MM:SS.fffffffff" (UTC) per packet
//   <drive>/oxts/data/NNNNNNNNNN.txt one packet per file: one line of 30 space-separated numbers
//
//   f1 lat  f2 lon [deg]  f3 alt [m]     f4 roll  f5 pitch  f6 yaw [rad]
//   f7 vn  f8 ve  f9 vf  f10 vl  f11 vu [m/s]    f12..f17 ax ay az af al au [m/s^2]
//   f18..f23 wx wy wz wf wl wu [rad/s]   f24 pos_accuracy  f25 vel_accuracy [m, m/s]
//   f26 navstat  f27 numsats  f28 posmode  f29 velmode  f30 orimode
//
// OXTS angles are already x2car's: world_from_ins = Rz(yaw) Ry(pitch) Rx(roll) with yaw 0 = east,
// counter-clockwise positive; roll positive = left side up, pitch positive = front down. The reader
// gives positions in a local ENU frame at the first packet (io/geodetic.hpp); velocity (ve, vn,
// vu) and attitude, which OXTS reports in the local-level axes at each packet, are turned into that
// frame's axes (a change below 0.01 deg per km travelled). Status is posmode as the device writes
// it.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <vector>

#include "x2car/io/geodetic.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::io {

constexpr std::size_t kOxtsFieldCount = 30;

// "lat", "lon", ..., "orimode": the names the reader's errors use, in file order.
std::span<const char* const> oxts_field_names();

struct OxtsLog {
  double start_unix_time = 0.0;    // UTC of the first packet [s since the Unix epoch]
  GeodeticPosition enu_origin;     // the first packet's position: the origin of position_enu
  std::vector<InsRecord> records;  // times [s] from the first packet, strictly increasing
  std::vector<TimeGap> gaps;       // forward jumps in the times; lines of timestamps.txt
};

// The folder holding data/ and timestamps.txt: `folder`/oxts when that is a directory, else
// `folder` itself.
std::filesystem::path oxts_folder_of(const std::filesystem::path& folder);

// Reads a KITTI drive folder (holding oxts/) or an oxts folder. Data files are the `*.txt` files of
// data/, taken in name order, one per timestamp. Throws InputError naming the file, line and field
// for: a missing timestamps.txt or data/, no data files, a count mismatch (both counts), a data
// file that is not one line of 30 numbers, a non-numeric or non-finite number, a latitude outside
// [-90, 90] deg, a non-integer posmode, an unparsable timestamp, and timestamps that do not
// strictly increase (how many, and the first line).
OxtsLog read_oxts_folder(const std::filesystem::path& folder);

}  // namespace x2car::io
