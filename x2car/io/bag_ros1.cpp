// ROS 1 bags through the ROS library itself (Debian's librosbag): its index gives the connections
// and the messages in time order. The only file that includes its headers (they are heavy).
#include <fmt/format.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"

namespace x2car::io {
namespace {

// The library loads its encryption plugins through class_loader's process-wide registry when a
// bag opens and unloads them when it closes, and that registry is not safe to use from several
// threads (two bags opened at once, as `calibrate all` does, fail to create rosbag::NoEncryptor).
// Opening and closing are serialised; reading two open bags at once is safe.
std::mutex& plugin_registry_mutex() {
  static std::mutex mutex;
  return mutex;
}

class Ros1Bag final : public BagFile {
 public:
  explicit Ros1Bag(std::filesystem::path path) : BagFile(std::move(path)) {
    // Held until the constructor ends, also when it throws: a bag that failed to open is closed
    // (bag_ reset) under the lock too.
    const std::lock_guard lock(plugin_registry_mutex());
    try {
      bag_ = std::make_unique<rosbag::Bag>();
      bag_->open(path_.string(), rosbag::bagmode::Read);
      rosbag::View all(*bag_);
      for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
        // A topic may have several connections (publishers); it is one topic here.
        if (topic_by_name_.contains(connection->topic)) continue;
        topic_by_name_[connection->topic] = topics_.size();
        topics_.push_back({.name = connection->topic,
                           .type = connection->datatype,
                           .encoding = "ros1",
                           .definition = connection->msg_def});
      }
    } catch (const rosbag::BagUnindexedException&) {
      bag_.reset();
      throw InputError(path_.string(),
                       "the bag has no index (a recording that did not close?): run `rosbag "
                       "reindex` on it first");
    } catch (const rosbag::BagException& error) {
      bag_.reset();
      throw InputError(path_.string(), fmt::format("not a readable ROS 1 bag: {}", error.what()));
    }
  }

  ~Ros1Bag() override {
    const std::lock_guard lock(plugin_registry_mutex());
    kept_.clear();
    bag_.reset();
  }
  Ros1Bag(const Ros1Bag&) = delete;
  Ros1Bag& operator=(const Ros1Bag&) = delete;

  BagContainer container() const override { return BagContainer::kRos1; }

  BagScanEnd scan_messages(
      const std::function<bool(const BagTopic&)>& wanted,
      const std::function<void(const BagMessage&)>& on_message,
      std::size_t /*data_prefix: the whole message is there anyway*/) override {
    std::vector<bool> topic_wanted;
    for (const BagTopic& topic : topics_) topic_wanted.push_back(!wanted || wanted(topic));
    std::string buffer;
    try {
      rosbag::View view(*bag_);
      for (const rosbag::MessageInstance& instance : view) {
        BagMessage message;
        message.topic = topic_by_name_.at(instance.getTopic());
        message.log_time_ns = static_cast<std::int64_t>(instance.getTime().toNSec());
        if (topic_wanted[message.topic]) {
          buffer = bytes_of(instance);
          message.data = buffer;
          message.ref.at = kept_.size();
          kept_.push_back(instance);
        }
        on_message(message);
      }
    } catch (const rosbag::BagException& error) {
      throw InputError(path_.string(), fmt::format("cannot read the bag: {}", error.what()));
    }
    return {.writer = "ROS 1 bag 2.0", .truncated_at = std::nullopt};
  }

  std::string read(const BagMessageRef& ref) const override {
    // The library reads through one file handle.
    const std::lock_guard lock(mutex_);
    if (ref.at >= kept_.size()) throw std::out_of_range("Ros1Bag::read: no such message");
    try {
      return bytes_of(kept_[ref.at]);
    } catch (const rosbag::BagException& error) {
      throw InputError(path_.string(), fmt::format("cannot read the bag: {}", error.what()));
    }
  }

 private:
  static std::string bytes_of(const rosbag::MessageInstance& instance) {
    std::string bytes(instance.size(), '\0');
    ros::serialization::OStream stream(reinterpret_cast<std::uint8_t*>(bytes.data()),
                                       static_cast<std::uint32_t>(bytes.size()));
    instance.write(stream);
    return bytes;
  }

  std::unique_ptr<rosbag::Bag> bag_;
  std::map<std::string, std::size_t> topic_by_name_;
  // The messages of wanted topics (the library's index entries), for read.
  std::vector<rosbag::MessageInstance> kept_;
  mutable std::mutex mutex_;
};

}  // namespace

std::unique_ptr<BagFile> open_ros1_bag(const std::filesystem::path& path) {
  return std::make_unique<Ros1Bag>(path);
}

}  // namespace x2car::io
