#include "x2car/io/mcap_ins.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
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
constexpr const char* kPoseStampedType = "geometry_msgs/msg/PoseStamped";
constexpr std::int64_t kUnixStampNs = 100'000'000LL * 1'000'000'000LL;  // 10^8 s

struct StampedRecord {
  std::int64_t stamp_ns = 0;
  InsRecord record;  // time unset
};

double finite(double value, const std::string& source, const char* field) {
  if (!std::isfinite(value)) throw InputError(source, 0, field, "not a finite number");
  return value;
}

// std_msgs/Header: the stamp [ns]; the frame id is read past.
std::int64_t read_stamp(CdrReader& cdr, const std::string& source) {
  const std::int32_t sec = cdr.int32("header.stamp.sec");
  const std::uint32_t nanosec = cdr.uint32("header.stamp.nanosec");
  if (nanosec >= 1'000'000'000U) {
    throw InputError(source, 0, "header.stamp.nanosec",
                     fmt::format("{} is not below 10^9", nanosec));
  }
  cdr.string("header.frame_id");
  return static_cast<std::int64_t>(sec) * 1'000'000'000LL + nanosec;
}

// geometry_msgs/Pose (`prefix` names it in messages, e.g. "pose.pose"): the position, and the
// orientation as world_from_device.
std::pair<Eigen::Vector3d, Eigen::Matrix3d> read_pose(CdrReader& cdr, const std::string& prefix,
                                                      const std::string& source) {
  const auto value = [&](const char* name) {
    const std::string field = prefix + name;
    return finite(cdr.float64(field.c_str()), source, field.c_str());
  };
  // One statement each: the fields are read in order (a constructor's arguments are not).
  Eigen::Vector3d position;
  position.x() = value(".position.x");
  position.y() = value(".position.y");
  position.z() = value(".position.z");
  const double qx = value(".orientation.x");
  const double qy = value(".orientation.y");
  const double qz = value(".orientation.z");
  const double qw = value(".orientation.w");
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (std::abs(q.norm() - 1.0) > 1e-2) {
    throw InputError(source, 0, prefix + ".orientation",
                     fmt::format("the quaternion has norm {}, not 1", format_number(q.norm())));
  }
  return {position, q.normalized().toRotationMatrix()};
}

// nav_msgs/msg/Odometry: header, child_frame_id, pose (Pose, covariance[36]), twist (linear xyz,
// angular xyz, covariance[36]); the twist in the device's axes.
StampedRecord decode_odometry(std::string_view bytes, const std::string& source) {
  CdrReader cdr(bytes, source);
  StampedRecord out;
  out.stamp_ns = read_stamp(cdr, source);
  cdr.string("child_frame_id");
  const auto [position, world_from_device] = read_pose(cdr, "pose.pose", source);
  cdr.skip_float64s(36, "pose.covariance");
  Eigen::Vector3d linear;
  linear.x() = finite(cdr.float64("twist.twist.linear.x"), source, "twist.twist.linear.x");
  linear.y() = finite(cdr.float64("twist.twist.linear.y"), source, "twist.twist.linear.y");
  linear.z() = finite(cdr.float64("twist.twist.linear.z"), source, "twist.twist.linear.z");
  out.record.position_enu = position;
  out.record.attitude = euler_from_rotation(world_from_device);
  out.record.velocity_enu = world_from_device * linear;
  return out;
}

// geometry_msgs/msg/PoseStamped: header, pose. No velocity: the calibrator differentiates the
// smoothed track (as for a CSV without velocity columns).
StampedRecord decode_pose_stamped(std::string_view bytes, const std::string& source) {
  CdrReader cdr(bytes, source);
  StampedRecord out;
  out.stamp_ns = read_stamp(cdr, source);
  const auto [position, world_from_device] = read_pose(cdr, "pose", source);
  out.record.position_enu = position;
  out.record.attitude = euler_from_rotation(world_from_device);
  return out;
}

bool is_pose_type(const std::string& type) {
  return type == kOdometryType || type == kPoseStampedType;
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
    if (!is_pose_type(channel.type)) return;
    if (options.topic && *options.topic != channel.topic) return;
    if (channel.encoding != "cdr") {
      throw InputError(file, 0, channel.topic,
                       fmt::format("the {} messages are encoded as '{}'; x2car reads ROS 2 CDR "
                                   "('cdr') here",
                                   channel.type, channel.encoding));
    }
    const std::string source =
        fmt::format("{} ({} message {})", file, channel.topic, channel.count);
    channel.records.push_back(channel.type == kOdometryType
                                  ? decode_odometry(message.data, source)
                                  : decode_pose_stamped(message.data, source));
  };
  read_mcap(path, handlers, {.allow_truncated = options.allow_truncated});

  std::vector<std::string> odometry_topics;
  for (const auto& [id, channel] : channels) {
    if (is_pose_type(channel.type)) odometry_topics.push_back(channel.topic);
  }
  Channel* chosen = nullptr;
  for (auto& [id, channel] : channels) {
    if (options.topic ? channel.topic == *options.topic : is_pose_type(channel.type)) {
      chosen = &channel;
      if (options.topic) break;
    }
  }
  if (options.topic && (chosen == nullptr || !is_pose_type(chosen->type))) {
    throw InputError(
        file, 0, *options.topic,
        chosen == nullptr
            ? fmt::format("no such topic; the pose topics: {}",
                          odometry_topics.empty() ? "none" : join(odometry_topics))
            : fmt::format("is {}, not {} or {}", chosen->type, kOdometryType, kPoseStampedType));
  }
  if (!options.topic && odometry_topics.size() != 1) {
    throw InputError(file, odometry_topics.empty()
                               ? fmt::format("holds no {} or {} topic for a GNSS/INS log",
                                             kOdometryType, kPoseStampedType)
                               : fmt::format("holds {} pose topics ({}): pick one with --topic",
                                             odometry_topics.size(), join(odometry_topics)));
  }
  std::vector<StampedRecord> stamped = std::move(chosen->records);
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
