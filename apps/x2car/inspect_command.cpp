// x2car inspect: what a log holds (issue 17 item 3): for an MCAP file its topics, their message
// types and encodings, counts, rates and time spans, and which calibrator could use each.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/mcap_reader.hpp"

namespace x2car::cli {
namespace {

struct InspectArguments {
  std::string input_path;
  bool allow_truncated = false;
};

struct TopicStats {
  std::string topic;
  std::string type;
  std::string encoding;
  std::int64_t count = 0;
  std::uint64_t first_ns = 0;
  std::uint64_t last_ns = 0;
  std::int64_t out_of_order = 0;  // messages logged before the one before them
  std::uint64_t previous_ns = 0;
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
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(arguments.input_path, "is not a file");
  }
  if (!io::looks_like_mcap(path) && std::filesystem::file_size(path) > 0) {
    throw InputError(arguments.input_path,
                     "not an MCAP file: x2car inspect reads MCAP (ROS 1 .bag and ROS 2 .db3 bags "
                     "are not read yet)");
  }
  std::map<std::uint16_t, std::string> schema_names;
  std::map<std::uint16_t, TopicStats> topics;
  io::McapHandlers handlers;
  handlers.on_schema = [&](const io::McapSchema& schema) { schema_names[schema.id] = schema.name; };
  handlers.on_channel = [&](const io::McapChannel& channel) {
    TopicStats& stats = topics[channel.id];
    stats.topic = channel.topic;
    stats.encoding = channel.message_encoding;
    const auto schema = schema_names.find(channel.schema_id);
    stats.type = schema == schema_names.end() ? "(no schema)" : schema->second;
  };
  handlers.on_message = [&](const io::McapMessage& message) {
    const auto found = topics.find(message.channel_id);
    if (found == topics.end()) {
      throw InputError(arguments.input_path,
                       fmt::format("a message on channel {}, which no channel record declares",
                                   message.channel_id));
    }
    TopicStats& stats = found->second;
    if (stats.count == 0) {
      stats.first_ns = stats.last_ns = message.log_time_ns;
    } else if (message.log_time_ns < stats.previous_ns) {
      ++stats.out_of_order;
    }
    stats.first_ns = std::min(stats.first_ns, message.log_time_ns);
    stats.last_ns = std::max(stats.last_ns, message.log_time_ns);
    stats.previous_ns = message.log_time_ns;
    ++stats.count;
  };
  const io::McapReadEnd end =
      io::read_mcap(path, handlers, {.allow_truncated = arguments.allow_truncated});

  std::int64_t messages = 0;
  std::optional<std::uint64_t> first;
  std::optional<std::uint64_t> last;
  for (const auto& [id, stats] : topics) {
    messages += stats.count;
    if (stats.count == 0) continue;
    first = std::min(first.value_or(stats.first_ns), stats.first_ns);
    last = std::max(last.value_or(stats.last_ns), stats.last_ns);
  }
  const double span_s = first ? static_cast<double>(*last - *first) * 1e-9 : 0.0;
  std::cout << fmt::format(
      "{}: MCAP, profile '{}', written by '{}'; {} topics, {} messages over "
      "{:.3f} s\n",
      arguments.input_path, end.profile, end.library, topics.size(), messages, span_s);
  if (end.truncated_at) {
    std::cout << fmt::format("cut short at byte {}: the counts are what comes before\n",
                             *end.truncated_at);
  }
  std::cout << fmt::format("{:<32} {:<34} {:<8} {:>9} {:>9} {:>11} {:>8}  {}\n", "topic", "type",
                           "encoding", "messages", "rate [Hz]", "span [s]", "late", "for");
  for (const auto& [id, stats] : topics) {
    const double topic_span_s = static_cast<double>(stats.last_ns - stats.first_ns) * 1e-9;
    const std::string rate =
        stats.count > 1 && topic_span_s > 0.0
            ? fmt::format("{:.2f}", static_cast<double>(stats.count - 1) / topic_span_s)
            : "—";
    std::cout << fmt::format("{:<32} {:<34} {:<8} {:>9} {:>9} {:>11.3f} {:>8}  {}\n", stats.topic,
                             stats.type, stats.encoding, stats.count, rate, topic_span_s,
                             stats.out_of_order, calibrator_for(stats.type));
  }
  std::cout
      << "(late: messages logged before the one before them on their topic. 'for': which "
         "calibrator's data a topic holds; from MCAP, x2car calibrates the GNSS/INS from a "
         "nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped topic in ROS 2 CDR (calibrate "
         "ins --input FILE --topic T); "
         "the other types are not read yet.)\n";
  return kExitOk;
}

}  // namespace

RunCommand setup_inspect_command(CLI::App& command) {
  auto arguments = std::make_shared<InspectArguments>();
  command.add_option("input", arguments->input_path, "The log file (MCAP)")
      ->type_name("FILE")
      ->required();
  command.add_flag("--allow-truncated", arguments->allow_truncated,
                   "Read a file cut short up to where it ends, instead of stopping with an error");
  command.footer(
      "Lists the topics of a log: message type, encoding, count, rate, time span, messages "
      "logged out of order, and which calibrator can use them.\n"
      "\n"
      "Example:\n"
      "  x2car inspect drive.mcap");
  return [arguments] { return run_inspect(*arguments); };
}

}  // namespace x2car::cli
