// The GNSS/INS log an `--input` or `--ins` argument names: a file as it is, or the log a drive
// folder holds (shared by calibrate ins, camera and radar).
#pragma once

#include <filesystem>

namespace x2car::cli {

// A drive folder (x2car simulate's layout, or any folder with an x2car.yaml manifest) gives its
// GNSS/INS log; InputError naming the folder when it has none. Any other path is returned as it
// is (a file, or a KITTI OXTS folder the log reader takes).
std::filesystem::path ins_log_of(const std::filesystem::path& input);

}  // namespace x2car::cli
