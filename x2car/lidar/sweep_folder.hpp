// Finding the sweeps of a LiDAR log in a folder, in time order (docs/formats.md, "LiDAR sweeps").
//
// A folder holds either
//   - PCD files (`*.pcd`, any case), one sweep each, named by the sweep's time: seconds with a
//     fraction ("000012.300000.pcd", "1541234567.123456.pcd"), whole nanoseconds since an epoch
//     (16 digits or more: "1541234567123456789.pcd") or ROS 2's seconds_nanoseconds
//     ("1541234567_123456789.pcd"); or any names plus a `times.txt` beside them
//     with one time [s] per file in name order; or any names, when the points hold absolute times
//     (Unix or GPS seconds, io/pcd.hpp): the earliest point's time is the sweep's; or
//   - KITTI scans: `velodyne/*.bin` with `times.txt` (one time [s] per scan, in name order) in the
//     folder itself; or
//   - KITTI raw scans: `velodyne_points/data/*.bin` with `velodyne_points/timestamps.txt` (one UTC
//     date-time per scan, the mid-sweep moment the scanner faced forward), the drive folder or
//     velodyne_points/ itself given.
// A simulate-style drive folder is accepted too: its `lidar/` subfolder is used. Other files are
// ignored and counted. The sweeps are returned sorted by time, whatever order the names sort in.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "x2car/io/point_cloud.hpp"

namespace x2car::lidar {

enum class SweepFileFormat { kPcd, kKittiBin };

struct SweepFile {
  std::filesystem::path path;
  double time = 0.0;  // the sweep's time stamp [s] (its start for the simulator's sweeps)
};

struct SweepFolder {
  std::filesystem::path folder;  // where the sweep files were found
  SweepFileFormat format = SweepFileFormat::kPcd;
  std::vector<SweepFile> sweeps;  // strictly increasing time
  std::size_t ignored_files = 0;  // files that are not sweeps of the chosen format
  std::string time_source;        // "file names" or the times file's path, for reports
};

// InputError naming the folder when it is missing, holds no sweeps, or the sweep times cannot be
// found; naming the file (and line) when a name or a times file does not parse, two sweeps have
// the same time, or a times file has a different number of lines than there are sweeps.
SweepFolder list_sweeps(const std::filesystem::path& folder);

// Reads one sweep in the folder's format (io/pcd.hpp, io/kitti_velodyne.hpp).
io::PointCloud read_sweep(const SweepFolder& folder, const SweepFile& sweep);

}  // namespace x2car::lidar
