#include "x2car/io/bag_ins.hpp"

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
#include "x2car/io/bag.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kPoseStampedType = "geometry_msgs/PoseStamped";
constexpr std::int64_t kUnixStampNs = 100'000'000LL * 1'000'000'000LL;  // 10^8 s

struct StampedRecord {
  std::int64_t stamp_ns = 0;
  InsRecord record;  // time unset
};

double finite(double value, const std::string& source, const char* field) {
  if (!std::isfinite(value)) throw InputError(source, 0, field, "not a finite number");
  return value;
}

// geometry_msgs/Pose (`prefix` names it in messages, e.g. "pose.pose"): the position, and the
// orientation as world_from_device.
std::pair<Eigen::Vector3d, Eigen::Matrix3d> read_pose(RosMessageReader& cdr, const std::string& prefix,
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
StampedRecord decode_odometry(std::string_view bytes, RosEncoding encoding,
                              const std::string& source) {
  RosMessageReader cdr(bytes, encoding, source);
  StampedRecord out;
  out.stamp_ns = cdr.header().stamp_ns;
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
StampedRecord decode_pose_stamped(std::string_view bytes, RosEncoding encoding,
                                  const std::string& source) {
  RosMessageReader cdr(bytes, encoding, source);
  StampedRecord out;
  out.stamp_ns = cdr.header().stamp_ns;
  const auto [position, world_from_device] = read_pose(cdr, "pose", source);
  out.record.position_enu = position;
  out.record.attitude = euler_from_rotation(world_from_device);
  return out;
}

bool is_pose_type(const std::string& type) {
  return ros_type_is(type, kOdometryType) || ros_type_is(type, kPoseStampedType);
}

}  // namespace

InsLog read_ins_bag(const std::filesystem::path& path, const BagInsOptions& options) {
  const std::string file = path.string();
  const std::unique_ptr<BagFile> bag = open_bag(path, {.allow_truncated = options.allow_truncated});
  const auto chosen_topic = [&](const BagTopic& topic) {
    return options.topic ? topic.name == *options.topic : is_pose_type(topic.type);
  };
  std::vector<StampedRecord> stamped;
  std::vector<std::int64_t> counts;
  bag->scan(chosen_topic, [&](const BagMessage& message) {
    counts.resize(bag->topics().size(), 0);
    const std::int64_t count = ++counts[message.topic];
    const BagTopic& topic = bag->topics()[message.topic];
    if (!chosen_topic(topic) || !is_pose_type(topic.type)) return;
    const RosEncoding encoding = ros_encoding_of(topic, path);
    const std::string source = fmt::format("{} ({} message {})", file, topic.name, count);
    stamped.push_back(ros_type_is(topic.type, kOdometryType)
                          ? decode_odometry(message.data, encoding, source)
                          : decode_pose_stamped(message.data, encoding, source));
  });

  std::vector<std::string> pose_topics;
  const BagTopic* chosen = nullptr;
  for (const BagTopic& topic : bag->topics()) {
    if (is_pose_type(topic.type)) pose_topics.push_back(topic.name);
    if (chosen_topic(topic) && chosen == nullptr) chosen = &topic;
  }
  if (options.topic && (chosen == nullptr || !is_pose_type(chosen->type))) {
    throw InputError(
        file, 0, *options.topic,
        chosen == nullptr
            ? fmt::format("no such topic; the pose topics: {}",
                          pose_topics.empty() ? "none" : join(pose_topics))
            : fmt::format("is {}, not {} or {}", chosen->type, kOdometryType, kPoseStampedType));
  }
  if (!options.topic && pose_topics.size() != 1) {
    throw InputError(file, pose_topics.empty()
                               ? fmt::format("holds no {} or {} topic for a GNSS/INS log",
                                             kOdometryType, kPoseStampedType)
                               : fmt::format("holds {} pose topics ({}): pick one with --topic",
                                             pose_topics.size(), join(pose_topics)));
  }
  if (stamped.empty()) throw InputError(file, 0, chosen->name, "the topic holds no messages");
  std::ranges::stable_sort(stamped, {}, &StampedRecord::stamp_ns);
  InsLog log;
  log.format = InsFormat::kBag;
  const std::int64_t first_ns = stamped.front().stamp_ns;
  const bool unix_clock = first_ns >= kUnixStampNs;
  if (unix_clock) log.start_unix_time = static_cast<double>(first_ns) * 1e-9;
  for (std::size_t i = 0; i < stamped.size(); ++i) {
    if (i > 0 && stamped[i].stamp_ns == stamped[i - 1].stamp_ns) {
      throw InputError(
          file, 0, chosen->name,
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
