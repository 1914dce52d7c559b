// Recorded logs as they come off a car (issue 17; docs/formats.md, "ROS bags"): one interface over
// the three containers ROS writes, so that each calibrator's reader handles a topic's messages
// without caring where they were stored:
//   - MCAP files (io/mcap_reader.hpp), ROS 2 CDR or ROS 1 message encodings;
//   - ROS 1 bags (`#ROSBAG V2.0`), read through the ROS library itself (Debian's librosbag);
//   - ROS 2 bags with the sqlite3 storage: a folder with `metadata.yaml` and its `.db3` files,
//     or one `.db3` file; a folder whose metadata names MCAP storage is read as its MCAP file.
// A bag is scanned once, message by message and never whole in memory; a message seen in the scan
// can be read again by its reference (from several threads at once), so that a LiDAR's sweeps are
// decoded in parallel after their times are known.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/ros_message.hpp"

namespace x2car::io {

enum class BagContainer { kMcap, kRos1, kRos2Sqlite };
const char* bag_container_name(BagContainer container);  // "MCAP", "ROS 1 bag", "ROS 2 bag"

struct BagTopic {
  std::string name;
  std::string type;        // as the bag spells it: "sensor_msgs/msg/Imu" or "sensor_msgs/Imu"
  std::string encoding;    // "cdr", "ros1", or another that x2car does not decode
  std::string definition;  // the message definition when the bag holds one
};

// True when `type` (either spelling) is `package_and_name`, e.g. "sensor_msgs/PointCloud2".
bool ros_type_is(std::string_view type, std::string_view package_and_name);

// The encoding of a topic's messages; InputError naming the file and the topic for one x2car
// does not decode.
RosEncoding ros_encoding_of(const BagTopic& topic, const std::filesystem::path& bag);

// Where a message lies, for BagFile::read.
struct BagMessageRef {
  std::uint64_t part = 0;  // MCAP: the chunk's offset (0: none); ROS 2: the .db3 file's index
  std::uint64_t at = 0;    // MCAP: the data's offset; ROS 1: the message's index; ROS 2: row id
  std::uint64_t size = 0;  // MCAP: the data's size
};

struct BagMessage {
  std::size_t topic = 0;         // index into BagFile::topics()
  std::int64_t log_time_ns = 0;  // when it was recorded (receive time), ns since the Unix epoch
  std::string_view data;         // empty for a topic not wanted; valid during the call only
  BagMessageRef ref;
};

struct BagOptions {
  // A file cut short (a recording that did not close) ends the scan instead of an error, where
  // the container allows it (MCAP).
  bool allow_truncated = false;
};

struct BagScanEnd {
  std::string writer;  // the library or ROS distribution that wrote it, when the bag says
  // Set when the file was cut short (allow_truncated): the byte where it ends.
  std::optional<std::uint64_t> truncated_at;
};

class BagFile {
 public:
  virtual ~BagFile() = default;
  BagFile(const BagFile&) = delete;
  BagFile& operator=(const BagFile&) = delete;

  virtual BagContainer container() const = 0;
  const std::filesystem::path& path() const { return path_; }
  // The topics known so far: every topic after scan (MCAP names its channels as it goes).
  const std::vector<BagTopic>& topics() const { return topics_; }

  // Every message, in file order (MCAP) or time order (ROS 1 and 2 bags); the data of topics for
  // which `wanted` is true (all when it is empty). `data_prefix` > 0: only that many of each
  // message's first bytes are needed (its header, when the data is read again later): a ROS 2 bag
  // then reads them alone, an MCAP file with a summary and message indexes decompresses its chunks
  // only that far (ROS 1 gives the whole message anyway), and `data` may be only that prefix; an
  // unwanted topic's message may come without `ref`. Throws InputError naming the file and, where
  // the container says, the byte offset.
  BagScanEnd scan(const std::function<bool(const BagTopic&)>& wanted,
                  const std::function<void(const BagMessage&)>& on_message,
                  std::size_t data_prefix = 0) {
    return scan_messages(wanted, on_message, data_prefix);
  }
  // The data of a message that scan delivered with data. Safe to call from several threads.
  virtual std::string read(const BagMessageRef& ref) const = 0;

 protected:
  explicit BagFile(std::filesystem::path path) : path_(std::move(path)) {}
  virtual BagScanEnd scan_messages(const std::function<bool(const BagTopic&)>& wanted,
                                   const std::function<void(const BagMessage&)>& on_message,
                                   std::size_t data_prefix) = 0;
  std::filesystem::path path_;
  std::vector<BagTopic> topics_;
};

// The topic a reader takes, after the scan: `wanted` when given (an InputError naming it when the
// bag has no such topic, listing those of `types`, or when it is of another type), else the bag's
// one topic of `types` (an InputError when it has none, or several: listing them, "pick one with
// --topic"). `kind` names the types in messages, e.g. "PointCloud2". Returns its index.
std::size_t choose_topic(const BagFile& bag, const std::optional<std::string>& wanted,
                         std::initializer_list<std::string_view> types, std::string_view kind);

// A message a reader keeps to read again (a LiDAR sweep, a camera frame).
struct StampedMessage {
  std::int64_t stamp_ns = 0;  // header.stamp
  BagMessageRef ref;
  std::size_t count = 0;  // the message's number on its topic, for errors
};

// Puts a topic's messages in stamp order (a stable sort) and returns their times [s]
// (stamp_seconds). InputError naming the bag and the topic when there are none, or two with one
// stamp.
std::vector<double> order_by_stamp(std::vector<StampedMessage>& messages, const BagFile& bag,
                                   const std::string& topic);

// A header stamp [ns] as seconds, rounded once from its decimal value: the same double as a file
// named by that time ("000012.300000.pcd", 12 s + 300000000 ns) or a timestamps file's line.
double stamp_seconds(std::int64_t stamp_ns);

// How the GNSS/INS and radar readers count time from header stamps: from the first stamp when it
// is 10^8 s or more (a Unix clock; the log keeps its Unix time apart), else as the stamps are (a
// simulation's clock).
struct StampClock {
  std::int64_t first_ns = 0;  // the first stamp, of the earliest message
  bool unix_clock = false;

  explicit StampClock(std::int64_t first_stamp_ns);
  double seconds(std::int64_t stamp_ns) const;    // the log's time of a stamp [s]
  std::optional<double> start_unix_time() const;  // of the first stamp, on a Unix clock [s]
};

// The container of `path`, by its first bytes or (a folder) its metadata.yaml; unset when it is
// none of them.
std::optional<BagContainer> bag_container_of(const std::filesystem::path& path);

// Opens a bag; InputError naming the path when it is not one, or cannot be read.
std::unique_ptr<BagFile> open_bag(const std::filesystem::path& path,
                                  const BagOptions& options = {});

// Per container (bag.cpp, bag_ros1.cpp, bag_ros2.cpp).
std::unique_ptr<BagFile> open_mcap_bag(const std::filesystem::path& path,
                                       const BagOptions& options);
std::unique_ptr<BagFile> open_ros1_bag(const std::filesystem::path& path);
std::unique_ptr<BagFile> open_ros2_bag(const std::filesystem::path& path,
                                       const BagOptions& options);

}  // namespace x2car::io
