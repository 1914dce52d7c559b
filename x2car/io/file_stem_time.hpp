// The time a data file's name gives, shared by the folder readers (LiDAR sweeps, camera images):
// a stem of seconds with a fraction ("1317357625.123456"), a whole number of 16 digits or more
// counting nanoseconds ("1317357625123456789", the ROS stamp), or ROS 2's seconds and nanoseconds
// joined by an underscore ("1317357625_123456789", the nanoseconds 1 to 9 digits, a count of
// nanoseconds: "5_1" is 5.000000001 s). Shorter whole numbers are sequence numbers
// ("0000000042"), not times.
#pragma once

#include <optional>
#include <string_view>

namespace x2car::io {

// The time [s] the stem names, or nothing when it is not a time.
std::optional<double> time_from_file_stem(std::string_view stem);

}  // namespace x2car::io
