#include "x2car/io/bag_radar.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr const char* kRadarScan = "radar_msgs/RadarScan";
constexpr const char* kRadarTracks = "radar_msgs/RadarTracks";

bool is_radar_type(const std::string& type) {
  return ros_type_is(type, kRadarScan) || ros_type_is(type, kRadarTracks);
}

struct StampedDetection {
  std::int64_t stamp_ns = 0;
  RadarDetection detection;  // time unset
};

void decode_scan(RosMessageReader& message, std::vector<StampedDetection>& out,
                 std::string& frame_id) {
  const RosHeader header = message.header();
  const std::int64_t stamp_ns = header.stamp_ns;
  if (frame_id.empty()) frame_id = header.frame_id;
  const std::uint32_t count = message.uint32("returns");
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string& source = message.source();
    RadarDetection detection;
    detection.range = finite_field(message.float32("returns.range"), source, "returns.range");
    detection.azimuth = finite_field(message.float32("returns.azimuth"), source, "returns.azimuth");
    message.float32("returns.elevation");
    detection.range_rate = finite_field(message.float32("returns.doppler_velocity"), source,
                                        "returns.doppler_velocity");
    detection.rcs_dbsm = message.float32("returns.amplitude");
    if (!std::isfinite(*detection.rcs_dbsm)) detection.rcs_dbsm.reset();
    detection.x = detection.range * std::cos(detection.azimuth);
    detection.y = detection.range * std::sin(detection.azimuth);
    out.push_back({.stamp_ns = stamp_ns, .detection = detection});
  }
}

void decode_tracks(RosMessageReader& message, std::map<std::string, int>& track_ids,
                   std::vector<StampedDetection>& out, std::string& frame_id) {
  const RosHeader header = message.header();
  const std::int64_t stamp_ns = header.stamp_ns;
  if (frame_id.empty()) frame_id = header.frame_id;
  const std::uint32_t count = message.uint32("tracks");
  const std::string& source = message.source();
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string uuid(message.fixed_bytes(16, "tracks.uuid"));
    RadarDetection detection;
    const auto [id, added] = track_ids.emplace(uuid, static_cast<int>(track_ids.size()));
    detection.track_id = id->second;
    detection.new_track = added;
    detection.x = finite_field(message.float64("tracks.position.x"), source, "tracks.position.x");
    detection.y = finite_field(message.float64("tracks.position.y"), source, "tracks.position.y");
    message.float64("tracks.position.z");
    detection.vx = finite_field(message.float64("tracks.velocity.x"), source, "tracks.velocity.x");
    detection.vy = finite_field(message.float64("tracks.velocity.y"), source, "tracks.velocity.y");
    detection.has_velocity = true;
    message.skip_float64s(7, "tracks.velocity.z, acceleration, size");
    message.uint16("tracks.classification");
    for (int j = 0; j < 4 * 6; ++j) message.float32("tracks covariances");
    set_polar_from_cartesian(detection);
    out.push_back({.stamp_ns = stamp_ns, .detection = detection});
  }
}

}  // namespace

RadarLog read_radar_bag(const std::filesystem::path& path, const BagRadarOptions& options) {
  const std::string file = path.string();
  const std::unique_ptr<BagFile> bag = open_bag(path, {.allow_truncated = options.allow_truncated});
  const auto chosen_topic = [&](const BagTopic& topic) {
    return options.topic ? topic.name == *options.topic : is_radar_type(topic.type);
  };
  std::vector<StampedDetection> stamped;
  std::map<std::string, int> track_ids;
  std::vector<std::int64_t> counts;
  std::string frame_id;
  bag->scan(chosen_topic, [&](const BagMessage& message) {
    counts.resize(bag->topics().size(), 0);
    const std::int64_t count = ++counts[message.topic];
    const BagTopic& topic = bag->topics()[message.topic];
    if (!chosen_topic(topic) || !is_radar_type(topic.type)) return;
    RosMessageReader reader(message.data, ros_encoding_of(topic, path),
                            fmt::format("{} ({} message {})", file, topic.name, count));
    if (ros_type_is(topic.type, kRadarScan)) {
      decode_scan(reader, stamped, frame_id);
    } else {
      decode_tracks(reader, track_ids, stamped, frame_id);
    }
  });

  const BagTopic& chosen =
      bag->topics()[choose_topic(*bag, options.topic, {kRadarScan, kRadarTracks}, "radar")];
  if (stamped.empty()) throw InputError(file, 0, chosen.name, "the topic holds no detections");
  std::ranges::stable_sort(stamped, {}, &StampedDetection::stamp_ns);

  RadarLog log;
  log.layout = RadarLayout::kBag;
  log.frame_id = frame_id;
  const StampClock clock(stamped.front().stamp_ns);
  if (clock.unix_clock) log.start_unix_time = *clock.start_unix_time();
  for (StampedDetection& entry : stamped) {
    entry.detection.time = clock.seconds(entry.stamp_ns);  // as the GNSS/INS bag reader's
    log.detections.push_back(entry.detection);
  }
  return log;
}

}  // namespace x2car::io
