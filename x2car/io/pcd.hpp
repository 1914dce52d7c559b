// PCD (Point Cloud Data, PCL's format v0.7) files of one LiDAR sweep.
//
// Writer: fields `x y z intensity ring t`, SIZE 4 4 4 4 2 4, TYPE F F F F U F (float32 x y z
// [m] in the LiDAR frame, float32 intensity 0..255, uint16 ring, float32 t [s] since the sweep's
// start), COUNT 1 each, WIDTH = number of points, HEIGHT 1, VIEWPOINT 0 0 0 1 0 0 0, little-endian;
// the data binary (the default), ascii or binary_compressed.
//
// Reader: ascii, binary and binary_compressed (LZF; each field's values stored together) data with
// any field order, SIZE 1/2/4/8 and TYPE F/U/I (F only 4 or 8), any COUNT for fields it does not
// use (padding such as PCL's `_`), COUNT 1 for the fields it uses: x y z (required), intensity (or
// i), ring, and a time named t, time or timestamp. Times of an integer TYPE are nanoseconds
// (Ouster's `t`), of a float TYPE seconds. When any time is 1e4 s or more (an absolute stamp, e.g.
// Unix or GPS seconds), PointCloud::time_base is the smallest time and t counts from it; otherwise
// time_base is 0. NaN coordinates are kept as NaN: callers skip and count them. Every other
// problem is an InputError naming the file, the header line and keyword (FIELDS, SIZE, TYPE, COUNT,
// WIDTH, HEIGHT, POINTS, DATA) or, for ascii data, the line and field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "x2car/io/point_cloud.hpp"

namespace x2car::io {

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

// The bytes of a PCD file holding `cloud` (all six fields, whatever its has_* flags say).
std::string format_pcd(const PointCloud& cloud, PcdEncoding encoding = PcdEncoding::kBinary);
// InputError naming the file when it cannot be written.
void write_pcd(const std::filesystem::path& path, const PointCloud& cloud,
               PcdEncoding encoding = PcdEncoding::kBinary);

PointCloud read_pcd(const std::filesystem::path& path);
// `bytes` is a whole file; `source_name` names it in errors.
PointCloud parse_pcd(std::string_view bytes, const std::string& source_name);

}  // namespace x2car::io
