// A radar's detections from a bag (io/bag.hpp: MCAP, ROS 1 or ROS 2; issue 17 item 2), as the ROS
// radar_msgs package publishes them (docs/formats.md, "ROS bags"):
//   - radar_msgs/RadarScan: header, RadarReturn[] returns (float32 range [m], azimuth [rad,
//     counter-clockwise, REP 103], elevation, doppler_velocity [m/s], amplitude [dB]). Each return
//     is a detection without a track id: range_rate = doppler_velocity (positive receding, the
//     radial speed's sign in every radar driver x2car knows; the calibrator's displacement check
//     flags a log with the opposite sign), x, y from range and azimuth in the radar's plane.
//   - radar_msgs/RadarTracks: header, RadarTrack[] tracks (UUID, position, velocity, ... in the
//     radar's frame, velocity relative to it, as the message documents). Each track is a
//     detection with a track id (one per UUID, numbered in order of appearance; new_track on its
//     first scan); range, azimuth and range_rate from x, y, vx, vy.
// Detections take their message's header.stamp. Unix stamps (10^8 s or more) count from the first
// one (RadarLog::start_unix_time), as the GNSS/INS bag reader counts its own; smaller stamps (a
// simulation's clock) are kept as they are.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "x2car/io/radar_csv.hpp"

namespace x2car::io {

struct BagRadarOptions {
  // The topic; unset: the bag's one RadarScan or RadarTracks topic (an error listing them when
  // there are more).
  std::optional<std::string> topic;
  bool allow_truncated = false;
};

// InputError naming the bag (and the topic or message) for a bag without a radar topic, an unknown
// or ambiguous topic, a message that ends early, or a non-finite value.
RadarLog read_radar_bag(const std::filesystem::path& path, const BagRadarOptions& options = {});

}  // namespace x2car::io
