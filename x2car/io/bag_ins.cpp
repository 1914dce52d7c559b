#include "x2car/io/bag_ins.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/geodetic.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/ros_definition.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kPoseStampedType = "geometry_msgs/PoseStamped";
constexpr const char* kNavSatFixType = "sensor_msgs/NavSatFix";
constexpr const char* kImuType = "sensor_msgs/Imu";
constexpr const char* kInspvaType = "novatel_oem7_msgs/INSPVA";
constexpr const char* kInspvaxType = "novatel_oem7_msgs/INSPVAX";

struct StampedRecord {
  std::int64_t stamp_ns = 0;
  std::string frame_id;  // Odometry's child frame: the device's
  InsRecord record;      // time unset
};

// geometry_msgs/Pose (`prefix` names it in messages, e.g. "pose.pose"): the position, and the
// orientation as world_from_device.
std::pair<Eigen::Vector3d, Eigen::Matrix3d> read_pose(RosMessageReader& cdr,
                                                      const std::string& prefix,
                                                      const std::string& source) {
  const auto value = [&](const char* name) {
    const std::string field = prefix + name;
    return finite_field(cdr.float64(field.c_str()), source, field.c_str());
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
  out.frame_id = cdr.string("child_frame_id");
  const auto [position, world_from_device] = read_pose(cdr, "pose.pose", source);
  cdr.skip_float64s(36, "pose.covariance");
  Eigen::Vector3d linear;
  linear.x() = finite_field(cdr.float64("twist.twist.linear.x"), source, "twist.twist.linear.x");
  linear.y() = finite_field(cdr.float64("twist.twist.linear.y"), source, "twist.twist.linear.y");
  linear.z() = finite_field(cdr.float64("twist.twist.linear.z"), source, "twist.twist.linear.z");
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

bool is_novatel_type(const std::string& type) {
  return ros_type_is(type, kInspvaType) || ros_type_is(type, kInspvaxType);
}

// A geodetic solution (NovAtel's INSPVA): position, local-level velocity and attitude.
struct GeodeticSample {
  std::int64_t stamp_ns = 0;
  GeodeticPosition position;
  Eigen::Vector3d velocity_local_level = Eigen::Vector3d::Zero();  // east, north, up [m/s]
  EulerAngles attitude_local_level;  // of local_level_from_device, x2car's axes [rad]
  int status = 0;
};

// novatel_oem7_msgs/INSPVA(X), read by the definition the bag holds (its Oem7Header has grown
// fields between driver versions). NovAtel's vehicle frame is x right, y forward, z up; its roll
// is right-handed about y (forward), its pitch right-handed about x (right: nose up positive),
// its azimuth clockwise from north, applied azimuth, pitch, roll. In x2car's axes (x forward, y
// left) that is Rz(pi/2 - azimuth) Ry(-pitch) Rx(roll).
GeodeticSample decode_inspva(const RosDefinition& definition, std::string_view bytes,
                             RosEncoding encoding, const std::string& source) {
  const bool ros1 = encoding == RosEncoding::kRos1;
  const std::string nanoseconds = ros1 ? "header.stamp.nsec" : "header.stamp.nanosec";
  const std::vector<std::string> paths = {
      "header.stamp.sec", nanoseconds,   "latitude", "longitude", "height",  "north_velocity",
      "east_velocity",    "up_velocity", "roll",     "pitch",     "azimuth", "status.status"};
  const std::map<std::string, double> values =
      definition.read_numbers(bytes, encoding, source, paths);
  const auto value = [&](const std::string& path) {
    const auto found = values.find(path);
    if (found == values.end()) {
      throw InputError(source, 0, path, "the message definition has no such field");
    }
    return finite_field(found->second, source, path.c_str());
  };
  GeodeticSample sample;
  const double sec = value("header.stamp.sec");
  const double nanosec = value(nanoseconds);
  if (nanosec < 0.0 || nanosec >= 1e9) {
    throw InputError(source, 0, nanoseconds, "is not below 10^9");
  }
  sample.stamp_ns =
      static_cast<std::int64_t>(sec) * 1'000'000'000LL + static_cast<std::int64_t>(nanosec);
  sample.position = {value("latitude"), value("longitude"), value("height")};
  if (!is_valid_geodetic(sample.position)) {
    throw InputError(source, 0, "latitude", "not a position on the earth");
  }
  sample.velocity_local_level = {value("east_velocity"), value("north_velocity"),
                                 value("up_velocity")};
  sample.attitude_local_level = {rad_from_deg(value("roll")), -rad_from_deg(value("pitch")),
                                 wrap_angle(kPi / 2.0 - rad_from_deg(value("azimuth")))};
  const auto status = values.find("status.status");
  sample.status = status == values.end() ? 0 : static_cast<int>(status->second);
  return sample;
}

// The samples in the ENU frame of the first (velocity and attitude turned from each sample's
// local level into it), as the other geodetic readers give them.
std::vector<StampedRecord> records_of(std::vector<GeodeticSample> samples,
                                      std::optional<GeodeticPosition>& origin) {
  std::ranges::stable_sort(samples, {}, &GeodeticSample::stamp_ns);
  std::vector<StampedRecord> out;
  if (samples.empty()) return out;
  const LocalEnuFrame frame(samples.front().position);
  origin = samples.front().position;
  for (const GeodeticSample& sample : samples) {
    const Eigen::Matrix3d frame_from_local_level = frame.frame_from_local_level(sample.position);
    StampedRecord record;
    record.stamp_ns = sample.stamp_ns;
    record.record.position_enu = frame.enu_from_geodetic(sample.position);
    record.record.velocity_enu = frame_from_local_level * sample.velocity_local_level;
    record.record.attitude = euler_from_rotation(frame_from_local_level *
                                                 rotation_from_euler(sample.attitude_local_level));
    record.record.status = sample.status;
    out.push_back(record);
  }
  return out;
}

// sensor_msgs/NavSatFix: header, status (int8 status, uint16 service), latitude, longitude,
// altitude, covariance[9], covariance type. Unset for a message without a fix (status < 0).
std::optional<std::pair<std::int64_t, GeodeticPosition>> decode_fix(RosMessageReader& message) {
  const std::int64_t stamp_ns = message.header().stamp_ns;
  const auto status = static_cast<std::int8_t>(message.uint8("status.status"));
  message.uint16("status.service");
  GeodeticPosition position;
  position.latitude_deg = message.float64("latitude");
  position.longitude_deg = message.float64("longitude");
  position.altitude_m = message.float64("altitude");
  if (status < 0) return std::nullopt;  // STATUS_NO_FIX
  if (!is_valid_geodetic(position)) {
    throw InputError(message.source(), 0, "latitude, longitude, altitude",
                     "not a position on the earth (latitude beyond +-90 deg or not finite)");
  }
  return std::pair{stamp_ns, position};
}

// sensor_msgs/Imu: header, orientation (x, y, z, w), orientation_covariance[9] ([0] = -1: no
// orientation), ... Unset for a message without an orientation.
struct ImuOrientation {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
  Eigen::Quaterniond local_level_from_imu;
};

std::optional<ImuOrientation> decode_imu(RosMessageReader& message) {
  ImuOrientation out;
  const RosHeader header = message.header();
  out.stamp_ns = header.stamp_ns;
  out.frame_id = header.frame_id;
  const double qx = message.float64("orientation.x");
  const double qy = message.float64("orientation.y");
  const double qz = message.float64("orientation.z");
  const double qw = message.float64("orientation.w");
  const double covariance = message.float64("orientation_covariance");
  if (covariance == -1.0) return std::nullopt;
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (!std::isfinite(q.norm()) || std::abs(q.norm() - 1.0) > 1e-2) {
    throw InputError(message.source(), 0, "orientation",
                     fmt::format("the quaternion has norm {}, not 1", format_number(q.norm())));
  }
  out.local_level_from_imu = q.normalized();
  return out;
}

// Per topic, what the scan decoded.
struct TopicData {
  std::vector<StampedRecord> poses;
  std::vector<GeodeticSample> geodetic;  // INSPVA
  std::optional<RosDefinition> definition;
  std::vector<std::pair<std::int64_t, GeodeticPosition>> fixes;
  std::vector<ImuOrientation> orientations;
  std::int64_t count = 0;
  std::int64_t without = 0;  // fixes without a fix, Imu messages without an orientation
};

// The fixes with the Imu's orientation at their stamps (spherical interpolation between the two
// samples around each; fixes outside the Imu's span are left out), positions and attitudes in the
// ENU frame of the first fix (the attitude turned from each fix's local level, as the other
// geodetic readers do). No velocity: the calibrator differentiates the track.
std::vector<StampedRecord> fixes_with_orientation(
    std::vector<std::pair<std::int64_t, GeodeticPosition>> fixes,
    std::vector<ImuOrientation> orientations, std::optional<GeodeticPosition>& origin) {
  std::ranges::stable_sort(fixes, {}, [](const auto& fix) { return fix.first; });
  std::ranges::stable_sort(orientations, {}, &ImuOrientation::stamp_ns);
  std::vector<StampedRecord> out;
  if (fixes.empty() || orientations.empty()) return out;
  const LocalEnuFrame frame(fixes.front().second);
  origin = fixes.front().second;
  std::size_t after = 0;
  for (const auto& [stamp_ns, position] : fixes) {
    while (after < orientations.size() && orientations[after].stamp_ns < stamp_ns) ++after;
    if (after == orientations.size()) break;
    Eigen::Quaterniond local_level_from_imu;
    if (orientations[after].stamp_ns == stamp_ns) {
      local_level_from_imu = orientations[after].local_level_from_imu;
    } else if (after == 0) {
      continue;
    } else {
      const ImuOrientation& before = orientations[after - 1];
      const ImuOrientation& next = orientations[after];
      const double share = static_cast<double>(stamp_ns - before.stamp_ns) /
                           static_cast<double>(next.stamp_ns - before.stamp_ns);
      local_level_from_imu = before.local_level_from_imu.slerp(share, next.local_level_from_imu);
    }
    StampedRecord record;
    record.stamp_ns = stamp_ns;
    record.record.position_enu = frame.enu_from_geodetic(position);
    record.record.attitude = euler_from_rotation(frame.frame_from_local_level(position) *
                                                 local_level_from_imu.toRotationMatrix());
    out.push_back(record);
  }
  return out;
}

// The one topic of `kind` (by --topic when it names one of them), or an InputError listing them.
const BagTopic* pick_topic(const std::vector<const BagTopic*>& candidates,
                           const std::optional<std::string>& wanted, const std::string& file,
                           const char* kind, const char* option) {
  if (wanted) {
    for (const BagTopic* topic : candidates) {
      if (topic->name == *wanted) return topic;
    }
    return nullptr;
  }
  if (candidates.size() == 1) return candidates.front();
  if (candidates.empty()) return nullptr;
  std::vector<std::string> names;
  for (const BagTopic* topic : candidates) names.push_back(topic->name);
  throw InputError(file, fmt::format("holds {} {} topics ({}): pick one with {}", names.size(),
                                     kind, join(names), option));
}

}  // namespace

bool is_ins_pose_type(const std::string& type) {
  return ros_type_is(type, kOdometryType) || ros_type_is(type, kPoseStampedType) ||
         is_novatel_type(type);
}

InsLog read_ins_bag(const std::filesystem::path& path, const BagInsOptions& options) {
  const std::string file = path.string();
  const std::unique_ptr<BagFile> bag = open_bag(path, {.allow_truncated = options.allow_truncated});
  const auto wanted = [&](const BagTopic& topic) {
    return is_ins_pose_type(topic.type) || ros_type_is(topic.type, kNavSatFixType) ||
           ros_type_is(topic.type, kImuType);
  };
  std::vector<TopicData> data;
  bag->scan(wanted, [&](const BagMessage& message) {
    data.resize(bag->topics().size());
    TopicData& topic_data = data[message.topic];
    const std::int64_t count = ++topic_data.count;
    const BagTopic& topic = bag->topics()[message.topic];
    if (!wanted(topic)) return;
    const RosEncoding encoding = ros_encoding_of(topic, path);
    const std::string source = fmt::format("{} ({} message {})", file, topic.name, count);
    if (ros_type_is(topic.type, kOdometryType)) {
      topic_data.poses.push_back(decode_odometry(message.data, encoding, source));
    } else if (ros_type_is(topic.type, kPoseStampedType)) {
      topic_data.poses.push_back(decode_pose_stamped(message.data, encoding, source));
    } else if (is_novatel_type(topic.type)) {
      if (!topic_data.definition) {
        if (topic.definition.empty()) {
          throw InputError(file, 0, topic.name,
                           fmt::format("the bag holds no message definition of {}: x2car reads "
                                       "NovAtel's messages by the definition the recorder stored",
                                       topic.type));
        }
        topic_data.definition.emplace(topic.type, topic.definition,
                                      fmt::format("{} ({} definition)", file, topic.name));
      }
      topic_data.geodetic.push_back(
          decode_inspva(*topic_data.definition, message.data, encoding, source));
    } else {
      RosMessageReader reader(message.data, encoding, source);
      if (ros_type_is(topic.type, kNavSatFixType)) {
        auto fix = decode_fix(reader);
        if (fix) topic_data.fixes.push_back(*fix);
        topic_data.without += fix ? 0 : 1;
      } else {
        auto orientation = decode_imu(reader);
        if (orientation) topic_data.orientations.push_back(*orientation);
        topic_data.without += orientation ? 0 : 1;
      }
    }
  });
  data.resize(bag->topics().size());

  std::vector<const BagTopic*> pose_topics;
  std::vector<const BagTopic*> fix_topics;
  std::vector<const BagTopic*> imu_topics;
  const BagTopic* named = nullptr;
  for (const BagTopic& topic : bag->topics()) {
    if (is_ins_pose_type(topic.type)) pose_topics.push_back(&topic);
    if (ros_type_is(topic.type, kNavSatFixType)) fix_topics.push_back(&topic);
    if (ros_type_is(topic.type, kImuType)) imu_topics.push_back(&topic);
    if (options.topic && topic.name == *options.topic) named = &topic;
  }
  const auto names_of = [](const std::vector<const BagTopic*>& topics) {
    std::vector<std::string> names;
    for (const BagTopic* topic : topics) names.push_back(topic->name);
    return names.empty() ? std::string("none") : join(names);
  };
  const auto index_of = [&](const BagTopic* topic) {
    return static_cast<std::size_t>(topic - bag->topics().data());
  };
  if (options.topic && (named == nullptr || !(is_ins_pose_type(named->type) ||
                                              ros_type_is(named->type, kNavSatFixType)))) {
    throw InputError(
        file, 0, *options.topic,
        named == nullptr
            ? fmt::format("no such topic; the pose topics: {}; the NavSatFix topics: {}",
                          names_of(pose_topics), names_of(fix_topics))
            : fmt::format("is {}, not {}, {} or {}", named->type, kOdometryType, kPoseStampedType,
                          kNavSatFixType));
  }

  InsLog log;
  log.format = InsFormat::kBag;
  std::vector<StampedRecord> stamped;
  const BagTopic* chosen = nullptr;
  if (named != nullptr ? is_ins_pose_type(named->type) : !pose_topics.empty()) {
    chosen =
        named != nullptr ? named : pick_topic(pose_topics, std::nullopt, file, "pose", "--topic");
    stamped = is_novatel_type(chosen->type)
                  ? records_of(std::move(data[index_of(chosen)].geodetic), log.enu_origin)
                  : std::move(data[index_of(chosen)].poses);
    if (!stamped.empty()) log.frame_id = stamped.front().frame_id;
  } else if (named != nullptr || !fix_topics.empty()) {
    // GNSS fixes with an IMU's orientation: what a car without an INS driver records.
    chosen = named != nullptr ? named
                              : pick_topic(fix_topics, std::nullopt, file, "NavSatFix", "--topic");
    const BagTopic* imu = pick_topic(imu_topics, options.imu_topic, file, "Imu", "--imu-topic");
    if (imu == nullptr) {
      throw InputError(
          file, 0, options.imu_topic.value_or(chosen->name),
          options.imu_topic
              ? fmt::format("no such Imu topic; the Imu topics: {}", names_of(imu_topics))
              : fmt::format("{} has no attitude: the bag needs a {} topic with an "
                            "orientation beside it",
                            chosen->name, kImuType));
    }
    TopicData& imu_data = data[index_of(imu)];
    if (imu_data.orientations.empty()) {
      throw InputError(file, 0, imu->name,
                       fmt::format("none of its {} messages carries an orientation "
                                   "(orientation_covariance[0] = -1)",
                                   imu_data.count));
    }
    log.frame_id = imu_data.orientations.front().frame_id;
    stamped = fixes_with_orientation(std::move(data[index_of(chosen)].fixes),
                                     std::move(imu_data.orientations), log.enu_origin);
    if (data[index_of(chosen)].without > 0) {
      log.notices.push_back(fmt::format("{} ({}): {} messages without a fix were left out", file,
                                        chosen->name, data[index_of(chosen)].without));
    }
  } else {
    throw InputError(file, fmt::format("holds no {}, {} or {} (with {}) topic for a GNSS/INS log",
                                       kOdometryType, kPoseStampedType, kNavSatFixType, kImuType));
  }
  if (stamped.empty()) {
    throw InputError(file, 0, chosen->name,
                     ros_type_is(chosen->type, kNavSatFixType)
                         ? "no fix falls within the Imu topic's time span"
                         : "the topic holds no messages");
  }
  std::ranges::stable_sort(stamped, {}, &StampedRecord::stamp_ns);
  const StampClock clock(stamped.front().stamp_ns);
  log.start_unix_time = clock.start_unix_time();
  for (std::size_t i = 0; i < stamped.size(); ++i) {
    if (i > 0 && stamped[i].stamp_ns == stamped[i - 1].stamp_ns) {
      throw InputError(
          file, 0, chosen->name,
          fmt::format("two messages stamped {} s", format_number(stamped[i].stamp_ns * 1e-9)));
    }
    InsRecord record = stamped[i].record;
    record.time = clock.seconds(stamped[i].stamp_ns);
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
