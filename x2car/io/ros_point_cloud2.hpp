// sensor_msgs/PointCloud2 messages (ROS 1 or ROS 2 encoding, io/ros_message.hpp) as x2car's
// PointCloud (docs/formats.md, "PointCloud2 field layouts"): whatever the driver's field layout.
//   - x, y, z: FLOAT32 or FLOAT64 [m] (required).
//   - intensity: `intensity` or `i`, else `reflectivity`; any numeric type.
//   - ring: `ring`, `line` (Livox), `laser_id` or `channel`; any integer type.
//   - per-point time: `t`, `time` or `offset_time` are relative to header.stamp, nanoseconds when
//     of an integer type (Ouster's uint32 `t`, Livox's `offset_time`), seconds when of a float
//     type (Velodyne's float32 `time`); `timestamp` is absolute (Hesai and Robosense: float64
//     seconds; Livox: float64 nanoseconds): whichever unit puts the values nearer header.stamp,
//     within a minute of it. PointCloud::t is then the time since header.stamp [s] (negative for
//     a driver that stamps a sweep at its end) and time_base is 0.
// Organised clouds (height > 1, e.g. Ouster's beams x columns) are read row by row (row_step);
// big-endian data is swapped; NaN coordinates are kept (callers skip them). Every other problem
// is an InputError naming the source and the field.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "x2car/io/point_cloud.hpp"
#include "x2car/io/ros_message.hpp"

namespace x2car::io {

struct StampedPointCloud {
  RosHeader header;
  PointCloud cloud;
};

// The header alone (the stamp and frame, read without the points).
RosHeader read_point_cloud2_header(std::string_view bytes, RosEncoding encoding,
                                   const std::string& source);

StampedPointCloud decode_point_cloud2(std::string_view bytes, RosEncoding encoding,
                                      const std::string& source);

}  // namespace x2car::io
