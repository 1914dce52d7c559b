#include "x2car/io/mcap_ins.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/mcap_reader.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/ros2_cdr.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr const char* kOdometryType = "nav_msgs/msg/Odometry";
constexpr std::int64_t kUnixStampNs = 100'000'000LL * 1'000'000'000LL;  // 10^8 s

struct StampedRecord {
  std::int64_t stamp_ns = 0;
  InsRecord record;  // time unset
};

double finite(double value, const std::string& source, const char* field) {
  if (!std::isfinite(value)) throw InputError(source, 0, field, "not a finite number");
  return value;
}

// nav_msgs/msg/Odometry: header (stamp sec, nanosec; frame_id), child_frame_id,
// pose (position xyz, orientation xyzw, covariance[36]), twist (linear xyz, angular xyz,
// covariance[36]).
StampedRecord decode_odometry(std::string_view bytes, const std::string& source) {
  CdrReader cdr(bytes, source);
  StampedRecord out;
  const std::int32_t sec = cdr.int32("header.stamp.sec");
  const std::uint32_t nanosec = cdr.uint32("header.stamp.nanosec");
  if (nanosec >= 1'000'000'000U) {
    throw InputError(source, 0, "header.stamp.nanosec",
                     fmt::format("{} is not below 10^9", nanosec));
  }
  out.stamp_ns = static_cast<std::int64_t>(sec) * 1'000'000'000LL + nanosec;
  cdr.string("header.frame_id");
  cdr.string("child_frame_id");
  Eigen::Vector3d position;
  position.x() = finite(cdr.float64("pose.pose.position.x"), source, "pose.pose.position.x");
  position.y() = finite(cdr.float64("pose.pose.position.y"), source, "pose.pose.position.y");
  position.z() = finite(cdr.float64("pose.pose.position.z"), source, "pose.pose.position.z");
  const double qx =
      finite(cdr.float64("pose.pose.orientation.x"), source, "pose.pose.orientation.x");
  const double qy =
      finite(cdr.float64("pose.pose.orientation.y"), source, "pose.pose.orientation.y");
  const double qz =
      finite(cdr.float64("pose.pose.orientation.z"), source, "pose.pose.orientation.z");
  const double qw =
      finite(cdr.float64("pose.pose.orientation.w"), source, "pose.pose.orientation.w");
  cdr.skip_float64s(36, "pose.covariance");
  Eigen::Vector3d linear;
  linear.x() = finite(cdr.float64("twist.twist.linear.x"), source, "twist.twist.linear.x");
  linear.y() = finite(cdr.float64("twist.twist.linear.y"), source, "twist.twist.linear.y");
  linear.z() = finite(cdr.float64("twist.twist.linear.z"), source, "twist.twist.linear.z");
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (std::abs(q.norm() - 1.0) > 1e-2) {
    throw InputError(source, 0, "pose.pose.orientation",
                     fmt::format("the quaternion has norm {}, not 1", format_number(q.norm())));
  }
  const Eigen::Matrix3d world_from_device = q.normalized().toRotationMatrix();
  out.record.position_enu = position;
  out.record.attitude = euler_from_rotation(world_from_device);
  out.record.velocity_enu = world_from_device * linear;
  return out;
}

struct Channel {
  std::string topic;
  std::string type;
  std::string encoding;
  std::vector<StampedRecord> records;
  std::int64_t count = 0;
};

}  // namespace

InsLog read_ins_mcap(const std::filesystem::path& path, const McapInsOptions& options) {
  const std::string file = path.string();
  std::map<std::uint16_t, std::string> schema_names;
  std::map<std::uint16_t, Channel> channels;
  McapHandlers handlers;
  handlers.on_schema = [&](const McapSchema& schema) { schema_names[schema.id] = schema.name; };
  handlers.on_channel = [&](const McapChannel& mcap_channel) {
    Channel& channel = channels[mcap_channel.id];
    channel.topic = mcap_channel.topic;
    channel.encoding = mcap_channel.message_encoding;
    const auto schema = schema_names.find(mcap_channel.schema_id);
    channel.type = schema == schema_names.end() ? std::string() : schema->second;
  };
  handlers.on_message = [&](const McapMessage& message) {
    const auto found = channels.find(message.channel_id);
    if (found == channels.end()) return;  // inspect names such files; a log reader skips them
    Channel& channel = found->second;
    ++channel.count;
    if (channel.type != kOdometryType) return;
    if (options.topic && *options.topic != channel.topic) return;
    if (channel.encoding != "cdr") {
      throw InputError(file, 0, channel.topic,
                       fmt::format("the Odometry messages are encoded as '{}'; x2car reads ROS 2 "
                                   "CDR ('cdr') here",
                                   channel.encoding));
    }
    channel.records.push_back(decode_odometry(
        message.data, fmt::format("{} ({} message {})", file, channel.topic, channel.count)));
  };
  read_mcap(path, handlers, {.allow_truncated = options.allow_truncated});

  std::vector<std::string> odometry_topics;
  for (const auto& [id, channel] : channels) {
    if (channel.type == kOdometryType) odometry_topics.push_back(channel.topic);
  }
  const Channel* chosen = nullptr;
  for (const auto& [id, channel] : channels) {
    if (options.topic ? channel.topic == *options.topic : channel.type == kOdometryType) {
      chosen = &channel;
      if (options.topic) break;
    }
  }
  if (options.topic && (chosen == nullptr || chosen->type != kOdometryType)) {
    throw InputError(file, 0, *options.topic,
                     chosen == nullptr
                         ? fmt::format("no such topic; the Odometry topics: {}",
                                       odometry_topics.empty() ? "none" : join(odometry_topics))
                         : fmt::format("is {}, not {}", chosen->type, kOdometryType));
  }
  if (!options.topic && odometry_topics.size() != 1) {
    throw InputError(file, odometry_topics.empty()
                               ? fmt::format("holds no {} topic for a GNSS/INS log", kOdometryType)
                               : fmt::format("holds {} Odometry topics ({}): pick one with --topic",
                                             odometry_topics.size(), join(odometry_topics)));
  }
  std::vector<StampedRecord> stamped = chosen->records;
  if (stamped.empty()) throw InputError(file, 0, chosen->topic, "the topic holds no messages");
  std::ranges::stable_sort(stamped, {}, &StampedRecord::stamp_ns);
  InsLog log;
  log.format = InsFormat::kMcap;
  const std::int64_t first_ns = stamped.front().stamp_ns;
  const bool unix_clock = first_ns >= kUnixStampNs;
  if (unix_clock) log.start_unix_time = static_cast<double>(first_ns) * 1e-9;
  for (std::size_t i = 0; i < stamped.size(); ++i) {
    if (i > 0 && stamped[i].stamp_ns == stamped[i - 1].stamp_ns) {
      throw InputError(
          file, 0, chosen->topic,
          fmt::format("two messages stamped {} s", format_number(stamped[i].stamp_ns * 1e-9)));
    }
    InsRecord record = stamped[i].record;
    record.time = unix_clock
                      ? seconds_between(stamped[i].stamp_ns, first_ns)
                      : static_cast<double>(stamped[i].stamp_ns / 1'000'000'000LL) +
                            static_cast<double>(stamped[i].stamp_ns % 1'000'000'000LL) * 1e-9;
    log.records.push_back(record);
  }
  std::vector<double> times;
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < log.records.size(); ++i) {
    times.push_back(log.records[i].time);
    indices.push_back(i + 1);
  }
  log.gaps = find_time_gaps(times, indices);
  return log;
}

}  // namespace x2car::io
