// KITTI's velodyne scans: one `.bin` file per sweep holding float32 x y z reflectance per point
// (little-endian, 16 bytes a point, no header), x y z in the LiDAR frame [m] and reflectance in
// [0, 1], and a `times.txt` beside the folder with one time per scan [s] (KITTI writes them as
// "%e"). The format has no ring or per-point time.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "x2car/io/point_cloud.hpp"

namespace x2car::io {

// Writes x y z and intensity / 255 (PointCloud intensities are 0..255, KITTI's 0..1). InputError
// naming the file when it cannot be written.
void write_kitti_velodyne(const std::filesystem::path& path, const PointCloud& cloud);

// Reads a scan; reflectance is scaled back to 0..255. InputError naming the file when its size is
// not a multiple of 16 bytes.
PointCloud read_kitti_velodyne(const std::filesystem::path& path);

// One time per line [s], "%.6e" like KITTI's times.txt.
std::string format_kitti_times(std::span<const double> times);
void write_kitti_times(const std::filesystem::path& path, std::span<const double> times);

}  // namespace x2car::io
