// A timestamps file as KITTI raw and the simulator write them beside images and LiDAR scans
// (`timestamps.txt`): one time per non-blank line, a UTC date-time `YYYY-MM-DD HH:MM:SS.fffffffff`
// (read as Unix seconds) or plain seconds, strictly increasing.
#pragma once

#include <filesystem>
#include <vector>

namespace x2car::io {

// The times [s]; InputError naming the file and line for a line that is not a time or a time
// that does not increase.
std::vector<double> read_timestamps_file(const std::filesystem::path& path);

}  // namespace x2car::io
