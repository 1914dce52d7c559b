// x2car inspect: what a log holds (issue 17 item 3): for a bag (MCAP, ROS 1, ROS 2; io/bag.hpp)
// its topics, their message types and encodings, counts, rates and time spans, and which
// calibrator could use each.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"

namespace x2car::cli {
namespace {

struct InspectArguments {
  std::string input_path;
  bool allow_truncated = false;
};

struct TopicStats {
  std::int64_t count = 0;
  std::int64_t first_ns = 0;
  std::int64_t last_ns = 0;
  std::int64_t out_of_order = 0;  // messages logged before the one before them
  std::int64_t previous_ns = 0;
};

// "sensor_msgs/msg/PointCloud2" and ROS 1's "sensor_msgs/PointCloud2" alike.
std::string plain_type(const std::string& type) {
  std::string plain = type;
  if (const auto at = plain.find("/msg/"); at != std::string::npos) plain.erase(at, 4);
  return plain;
}

// Which calibrator's data a message type is (issue 17 item 2's types).
std::string calibrator_for(const std::string& type) {
  static const std::map<std::string, std::string> kUses = {
      {"sensor_msgs/PointCloud2", "lidar"},
      {"sensor_msgs/Imu", "ins"},
      {"sensor_msgs/NavSatFix", "ins"},
      {"nav_msgs/Odometry", "ins"},
      {"geometry_msgs/PoseStamped", "ins"},
      {"novatel_oem7_msgs/INSPVA", "ins"},
      {"novatel_oem7_msgs/INSPVAX", "ins"},
      {"sensor_msgs/Image", "camera"},
      {"sensor_msgs/CompressedImage", "camera"},
      {"sensor_msgs/CameraInfo", "camera (intrinsics)"},
      {"radar_msgs/RadarScan", "radar"},
      {"radar_msgs/RadarTracks", "radar"},
      {"tf2_msgs/TFMessage", "prior mountings (tf)"},
  };
  const auto found = kUses.find(plain_type(type));
  return found == kUses.end() ? "—" : found->second;
}

int run_inspect(const InspectArguments& arguments) {
  const std::filesystem::path path(arguments.input_path);
  const std::unique_ptr<io::BagFile> bag =
      io::open_bag(path, {.allow_truncated = arguments.allow_truncated});
  std::vector<TopicStats> topics;
  // Only the times are needed: no topic's data is asked for (MCAP decompresses its chunks anyway).
  const io::BagScanEnd end =
      bag->scan([](const io::BagTopic&) { return false; },
                [&](const io::BagMessage& message) {
                  topics.resize(bag->topics().size());
                  TopicStats& stats = topics[message.topic];
                  if (stats.count == 0) {
                    stats.first_ns = stats.last_ns = message.log_time_ns;
                  } else if (message.log_time_ns < stats.previous_ns) {
                    ++stats.out_of_order;
                  }
                  stats.first_ns = std::min(stats.first_ns, message.log_time_ns);
                  stats.last_ns = std::max(stats.last_ns, message.log_time_ns);
                  stats.previous_ns = message.log_time_ns;
                  ++stats.count;
                });
  topics.resize(bag->topics().size());

  std::int64_t messages = 0;
  std::optional<std::int64_t> first;
  std::optional<std::int64_t> last;
  for (const TopicStats& stats : topics) {
    messages += stats.count;
    if (stats.count == 0) continue;
    first = std::min(first.value_or(stats.first_ns), stats.first_ns);
    last = std::max(last.value_or(stats.last_ns), stats.last_ns);
  }
  const double span_s = first ? static_cast<double>(*last - *first) * 1e-9 : 0.0;
  std::cout << fmt::format("{}: {}, written by '{}'; {} topics, {} messages over {:.3f} s\n",
                           arguments.input_path, io::bag_container_name(bag->container()),
                           end.writer, topics.size(), messages, span_s);
  if (end.truncated_at) {
    std::cout << fmt::format("cut short at byte {}: the counts are what comes before\n",
                             *end.truncated_at);
  }
  std::cout << fmt::format("{:<32} {:<34} {:<8} {:>9} {:>9} {:>11} {:>8}  {}\n", "topic", "type",
                           "encoding", "messages", "rate [Hz]", "span [s]", "late", "for");
  for (std::size_t i = 0; i < topics.size(); ++i) {
    const TopicStats& stats = topics[i];
    const io::BagTopic& topic = bag->topics()[i];
    const double topic_span_s = static_cast<double>(stats.last_ns - stats.first_ns) * 1e-9;
    const std::string rate =
        stats.count > 1 && topic_span_s > 0.0
            ? fmt::format("{:.2f}", static_cast<double>(stats.count - 1) / topic_span_s)
            : "—";
    std::cout << fmt::format("{:<32} {:<34} {:<8} {:>9} {:>9} {:>11.3f} {:>8}  {}\n", topic.name,
                             topic.type.empty() ? "(no schema)" : topic.type, topic.encoding,
                             stats.count, rate, topic_span_s, stats.out_of_order,
                             calibrator_for(topic.type));
  }
  std::cout << "(late: messages logged before the one before them on their topic. 'for': which "
               "calibrator reads a topic: calibrate <for> --input BAG --topic T; tf topics are "
               "not read yet.)\n";
  return kExitOk;
}

}  // namespace

RunCommand setup_inspect_command(CLI::App& command) {
  auto arguments = std::make_shared<InspectArguments>();
  command
      .add_option("input", arguments->input_path,
                  "The log: an MCAP file, a ROS 1 .bag, or a ROS 2 bag folder (or its .db3 file)")
      ->type_name("BAG")
      ->required();
  command.add_flag("--allow-truncated", arguments->allow_truncated,
                   "Read a file cut short up to where it ends, instead of stopping with an error");
  command.footer(
      "Lists the topics of a log: message type, encoding, count, rate, time span, messages "
      "logged out of order, and which calibrator can use them.\n"
      "\n"
      "Example:\n"
      "  x2car inspect drive.mcap\n"
      "  x2car inspect rosbag2_2026_11_26-10_00_00/");
  return [arguments] { return run_inspect(*arguments); };
}

}  // namespace x2car::cli
