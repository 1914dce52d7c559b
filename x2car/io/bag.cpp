#include "x2car/io/bag.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <utility>

#include "x2car/core/error.hpp"
#include "x2car/io/mcap_reader.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// An MCAP file as a bag: channels become topics as the stream names them.
class McapBag final : public BagFile {
 public:
  McapBag(std::filesystem::path path, const BagOptions& options)
      : BagFile(std::move(path)), options_(options) {}

  BagContainer container() const override { return BagContainer::kMcap; }

  BagScanEnd scan_messages(const std::function<bool(const BagTopic&)>& wanted,
                           const std::function<void(const BagMessage&)>& on_message,
                           std::size_t data_prefix) override {
    std::map<std::uint16_t, McapSchema> schemas;
    std::map<std::uint16_t, std::size_t> topic_of_channel;
    std::vector<bool> topic_wanted(topics_.size(), false);
    std::map<std::string, std::size_t> topic_by_name;
    for (std::size_t i = 0; i < topics_.size(); ++i) {
      topic_by_name[topics_[i].name] = i;
      topic_wanted[i] = !wanted || wanted(topics_[i]);
    }
    McapHandlers handlers;
    handlers.on_schema = [&](const McapSchema& schema) { schemas[schema.id] = schema; };
    handlers.on_channel = [&](const McapChannel& channel) {
      const auto schema = schemas.find(channel.schema_id);
      BagTopic topic{.name = channel.topic,
                     .type = schema == schemas.end() ? std::string() : schema->second.name,
                     .encoding = channel.message_encoding,
                     .definition = schema == schemas.end() ? std::string() : schema->second.data};
      // A topic may have several channels (publishers); it is one topic here.
      auto [known, added] = topic_by_name.emplace(topic.name, topics_.size());
      if (added) {
        topics_.push_back(std::move(topic));
        topic_wanted.push_back(!wanted || wanted(topics_.back()));
      }
      topic_of_channel[channel.id] = known->second;
    };
    handlers.on_message = [&](const McapMessage& message) {
      const auto topic = topic_of_channel.find(message.channel_id);
      if (topic == topic_of_channel.end()) {
        throw InputError(path_.string(),
                         fmt::format("a message on channel {}, which the file never describes",
                                     message.channel_id));
      }
      BagMessage out;
      out.topic = topic->second;
      out.log_time_ns = static_cast<std::int64_t>(message.log_time_ns);
      if (topic_wanted[out.topic]) out.data = message.data;
      out.ref = {
          .part = message.chunk_offset, .at = message.data_offset, .size = message.data_size};
      on_message(out);
    };
    // With a data prefix, chunks are decompressed only as far as the wanted messages' prefixes
    // reach (mcap_reader.hpp): a compressed sweep is then decompressed once, when it is read.
    const McapReadEnd end =
        read_mcap(path_, handlers,
                  {.allow_truncated = options_.allow_truncated,
                   .data_prefix = data_prefix,
                   .wants_data = [&](std::uint16_t channel_id) {
                     const auto topic = topic_of_channel.find(channel_id);
                     return topic != topic_of_channel.end() && topic_wanted[topic->second];
                   }});
    return {.writer = end.library, .truncated_at = end.truncated_at};
  }

  std::string read(const BagMessageRef& ref) const override {
    return read_mcap_message(path_, ref.part, ref.at, ref.size);
  }

 private:
  BagOptions options_;
};

constexpr std::string_view kRos1Magic = "#ROSBAG V2.0\n";
constexpr std::string_view kSqliteMagic = std::string_view("SQLite format 3\0", 16);
constexpr std::string_view kMcapMagic = "\x89MCAP0\r\n";

}  // namespace

const char* bag_container_name(BagContainer container) {
  switch (container) {
    case BagContainer::kMcap:
      return "MCAP";
    case BagContainer::kRos1:
      return "ROS 1 bag";
    case BagContainer::kRos2Sqlite:
      return "ROS 2 bag";
  }
  return "bag";
}

double stamp_seconds(std::int64_t stamp_ns) {
  const std::string text =
      fmt::format("{}{}.{:09}", stamp_ns < 0 ? "-" : "", std::abs(stamp_ns / 1'000'000'000LL),
                  std::abs(stamp_ns % 1'000'000'000LL));
  double seconds = 0.0;
  std::from_chars(text.data(), text.data() + text.size(), seconds);
  return seconds;
}

StampClock::StampClock(std::int64_t first_stamp_ns)
    : first_ns(first_stamp_ns), unix_clock(first_stamp_ns >= 100'000'000LL * 1'000'000'000LL) {}

double StampClock::seconds(std::int64_t stamp_ns) const {
  return unix_clock ? seconds_between(stamp_ns, first_ns)
                    : static_cast<double>(stamp_ns / 1'000'000'000LL) +
                          static_cast<double>(stamp_ns % 1'000'000'000LL) * 1e-9;
}

std::optional<double> StampClock::start_unix_time() const {
  if (!unix_clock) return std::nullopt;
  return static_cast<double>(first_ns) * 1e-9;
}

std::size_t choose_topic(const BagFile& bag, const std::optional<std::string>& wanted,
                         std::initializer_list<std::string_view> types, std::string_view kind) {
  const auto of_types = [&](const BagTopic& topic) {
    return std::ranges::any_of(
        types, [&](std::string_view type) { return ros_type_is(topic.type, type); });
  };
  std::vector<std::string> candidates;
  std::optional<std::size_t> named;
  std::optional<std::size_t> only;
  for (std::size_t i = 0; i < bag.topics().size(); ++i) {
    const BagTopic& topic = bag.topics()[i];
    if (of_types(topic)) {
      candidates.push_back(topic.name);
      only = i;
    }
    if (wanted && topic.name == *wanted) named = i;
  }
  const std::string file = bag.path().string();
  std::vector<std::string> type_names(types.begin(), types.end());
  if (wanted) {
    if (!named) {
      throw InputError(file, 0, *wanted,
                       fmt::format("no such topic; the {} topics: {}", kind,
                                   candidates.empty() ? "none" : join(candidates)));
    }
    if (!of_types(bag.topics()[*named])) {
      throw InputError(
          file, 0, *wanted,
          fmt::format("is {}, not {}", bag.topics()[*named].type, join(type_names, " or ")));
    }
    return *named;
  }
  if (candidates.size() != 1) {
    throw InputError(file, candidates.empty()
                               ? fmt::format("holds no {} topic", join(type_names, " or "))
                               : fmt::format("holds {} {} topics ({}): pick one with --topic",
                                             candidates.size(), kind, join(candidates)));
  }
  return *only;
}

std::vector<double> order_by_stamp(std::vector<StampedMessage>& messages, const BagFile& bag,
                                   const std::string& topic) {
  const std::string file = bag.path().string();
  if (messages.empty()) throw InputError(file, 0, topic, "the topic holds no messages");
  std::ranges::stable_sort(messages, {}, &StampedMessage::stamp_ns);
  std::vector<double> times;
  times.reserve(messages.size());
  for (std::size_t i = 0; i < messages.size(); ++i) {
    if (i > 0 && messages[i].stamp_ns == messages[i - 1].stamp_ns) {
      throw InputError(
          file, 0, topic,
          fmt::format("messages {} and {} have one header.stamp ({} s)", messages[i - 1].count,
                      messages[i].count, stamp_seconds(messages[i].stamp_ns)));
    }
    times.push_back(stamp_seconds(messages[i].stamp_ns));
  }
  return times;
}

bool ros_type_is(std::string_view type, std::string_view package_and_name) {
  const std::size_t slash = package_and_name.find('/');
  if (slash == std::string_view::npos) return false;
  if (type == package_and_name) return true;
  // ROS 2 spells it "package/msg/Name".
  return type.size() == package_and_name.size() + 4 &&
         type.substr(0, slash) == package_and_name.substr(0, slash) &&
         type.substr(slash, 5) == "/msg/" &&
         type.substr(slash + 5) == package_and_name.substr(slash + 1);
}

RosEncoding ros_encoding_of(const BagTopic& topic, const std::filesystem::path& bag) {
  if (topic.encoding == "cdr") return RosEncoding::kCdr;
  if (topic.encoding == "ros1") return RosEncoding::kRos1;
  throw InputError(bag.string(), 0, topic.name,
                   fmt::format("the {} messages are encoded as '{}'; x2car reads ROS 2 CDR "
                               "('cdr') and ROS 1 ('ros1') messages",
                               topic.type, topic.encoding));
}

std::optional<BagContainer> bag_container_of(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    if (std::filesystem::is_regular_file(path / "metadata.yaml", error)) {
      return BagContainer::kRos2Sqlite;
    }
    return std::nullopt;
  }
  std::ifstream stream(path, std::ios::binary);
  std::array<char, 16> start{};
  stream.read(start.data(), start.size());
  const std::string_view head(start.data(), static_cast<std::size_t>(stream.gcount()));
  if (head.starts_with(kMcapMagic)) return BagContainer::kMcap;
  if (head.starts_with(kRos1Magic)) return BagContainer::kRos1;
  if (head.starts_with(kSqliteMagic)) return BagContainer::kRos2Sqlite;
  return std::nullopt;
}

std::unique_ptr<BagFile> open_mcap_bag(const std::filesystem::path& path,
                                       const BagOptions& options) {
  return std::make_unique<McapBag>(path, options);
}

std::unique_ptr<BagFile> open_bag(const std::filesystem::path& path, const BagOptions& options) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw InputError(path.string(), "no such file");
  const std::optional<BagContainer> container = bag_container_of(path);
  if (!container) {
    if (std::filesystem::is_regular_file(path, error) && std::filesystem::file_size(path) == 0) {
      throw InputError(path.string(), "the file is empty");
    }
    throw InputError(path.string(),
                     std::filesystem::is_directory(path, error)
                         ? "not a ROS 2 bag folder (no metadata.yaml)"
                         : "not a bag: neither MCAP, a ROS 1 bag nor a ROS 2 .db3 file");
  }
  switch (*container) {
    case BagContainer::kMcap:
      return open_mcap_bag(path, options);
    case BagContainer::kRos1:
      return open_ros1_bag(path);
    case BagContainer::kRos2Sqlite:
      return open_ros2_bag(path, options);
  }
  throw std::logic_error("open_bag: unknown container");
}

}  // namespace x2car::io
