#include "x2car/lidar/bag_sweeps.hpp"

#include <fmt/format.h>

#include <memory>
#include <utility>
#include <vector>

#include "x2car/io/bag.hpp"
#include "x2car/io/ros_point_cloud2.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::lidar {
namespace {

constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";

}  // namespace

BagSweeps sweeps_from_bag(const std::filesystem::path& path, const BagSweepOptions& options) {
  const std::string file = path.string();
  std::unique_ptr<io::BagFile> bag =
      io::open_bag(path, {.allow_truncated = options.allow_truncated});
  const auto chosen_topic = [&](const io::BagTopic& topic) {
    return options.topic ? topic.name == *options.topic : io::ros_type_is(topic.type, kPointCloud2);
  };
  // Per topic index: its sweeps.
  std::vector<std::vector<io::StampedMessage>> messages;
  std::vector<std::size_t> counts;
  std::string frame_id;
  // The scan reads each sweep's header alone where the container allows (64 KiB holds it).
  constexpr std::size_t kHeaderBytes = 64 * 1024;
  bag->scan(
      chosen_topic,
      [&](const io::BagMessage& message) {
        messages.resize(bag->topics().size());
        counts.resize(bag->topics().size(), 0);
        const std::size_t count = ++counts[message.topic];
        const io::BagTopic& topic = bag->topics()[message.topic];
        if (!chosen_topic(topic) || !io::ros_type_is(topic.type, kPointCloud2)) return;
        const std::string source = fmt::format("{} ({} message {})", file, topic.name, count);
        const io::RosHeader header =
            io::read_point_cloud2_header(message.data, io::ros_encoding_of(topic, path), source);
        if (messages[message.topic].empty()) frame_id = header.frame_id;
        messages[message.topic].push_back(
            {.stamp_ns = header.stamp_ns, .ref = message.ref, .count = count});
      },
      kHeaderBytes);

  const std::size_t chosen = io::choose_topic(*bag, options.topic, {kPointCloud2}, "PointCloud2");
  const io::BagTopic topic = bag->topics()[chosen];
  std::vector<io::StampedMessage> sweeps =
      chosen < messages.size() ? std::move(messages[chosen]) : std::vector<io::StampedMessage>{};
  BagSweeps out;
  out.topic = topic.name;
  out.frame_id = frame_id;
  out.source.times = io::order_by_stamp(sweeps, *bag, topic.name);
  const io::RosEncoding encoding = io::ros_encoding_of(topic, path);
  // Shared: the source may be copied, and outlives this call.
  out.source.read = [bag = std::shared_ptr<const io::BagFile>(std::move(bag)),
                     sweeps = std::move(sweeps), encoding, file,
                     name = topic.name](std::size_t index) {
    const io::StampedMessage& sweep = sweeps.at(index);
    const std::string bytes = bag->read(sweep.ref);
    return io::decode_point_cloud2(bytes, encoding,
                                   fmt::format("{} ({} message {})", file, name, sweep.count))
        .cloud;
  };
  return out;
}

}  // namespace x2car::lidar
