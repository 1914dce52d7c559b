// One LiDAR sweep as x2car's readers, writers and simulator exchange it: points in the sensor frame
// (x forward, y left, z up; DESIGN §1), each with its intensity, beam (ring) and time within the
// sweep, so that a sweep distorted by the car's motion can be corrected point by point.
#pragma once

#include <cstdint>
#include <vector>

namespace x2car::io {

struct LidarPoint {
  // Position in the LiDAR frame at the time the point was measured [m]. Files may hold NaN for
  // beams without a return; readers keep them as NaN and callers skip them.
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
  float intensity =
      0.0f;  // return strength, 0..255 (the simulator's: reflectivity x cos incidence)
  std::uint16_t ring = 0;  // beam index; the simulator numbers beams from the lowest elevation up
  float t = 0.0f;          // time since the start of the sweep [s]
};

struct PointCloud {
  std::vector<LidarPoint> points;
  // Which of the optional fields the source held; absent fields read as 0.
  bool has_intensity = false;
  bool has_ring = false;
  bool has_time = false;
  // The absolute time that `t` counts from [s], when the source held absolute stamps (see
  // pcd.hpp); 0 when its times were already relative to the sweep.
  double time_base = 0.0;
};

}  // namespace x2car::io
