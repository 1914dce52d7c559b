// ROS 2 bags as `ros2 bag record` writes them (rosbag2): a folder with metadata.yaml that names
// its storage and files. The sqlite3 storage (Foxy to Humble's default) is read here through
// libsqlite3: tables `topics` (id, name, type, serialization_format) and `messages` (id,
// topic_id, timestamp [ns], data), the files of a split bag one after another. A folder whose
// storage is MCAP (Iron's default) is read as its MCAP file. One .db3 file can be given alone.
#include <fmt/format.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

struct SqliteCloser {
  void operator()(sqlite3* database) const { sqlite3_close(database); }
};
struct StatementFinalizer {
  void operator()(sqlite3_stmt* statement) const { sqlite3_finalize(statement); }
};
using Database = std::unique_ptr<sqlite3, SqliteCloser>;
using Statement = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

class Ros2SqliteBag final : public BagFile {
 public:
  Ros2SqliteBag(std::filesystem::path path, std::vector<std::filesystem::path> files)
      : BagFile(std::move(path)), files_(std::move(files)) {
    std::map<std::string, std::size_t> topic_by_name;
    for (std::size_t part = 0; part < files_.size(); ++part) {
      databases_.push_back(open(files_[part]));
      std::map<std::int64_t, std::size_t> topic_of_id;
      Statement topics = prepare(part, "SELECT id, name, type, serialization_format FROM topics");
      while (step(part, topics.get())) {
        BagTopic topic{.name = text(topics.get(), 1),
                       .type = text(topics.get(), 2),
                       .encoding = text(topics.get(), 3),
                       .definition = {}};
        auto [known, added] = topic_by_name.emplace(topic.name, topics_.size());
        if (added) topics_.push_back(std::move(topic));
        topic_of_id[sqlite3_column_int64(topics.get(), 0)] = known->second;
      }
      topic_of_id_.push_back(std::move(topic_of_id));
    }
  }

  BagContainer container() const override { return BagContainer::kRos2Sqlite; }

  BagScanEnd scan_messages(const std::function<bool(const BagTopic&)>& wanted,
                           const std::function<void(const BagMessage&)>& on_message,
                           std::size_t data_prefix) override {
    std::vector<bool> topic_wanted;
    for (const BagTopic& topic : topics_) topic_wanted.push_back(!wanted || wanted(topic));
    std::string data;  // the current message's
    for (std::size_t part = 0; part < files_.size(); ++part) {
      // The data column is not in the query (ordering would carry every blob through the sorter);
      // a wanted message's data is read by its row through the incremental blob I/O.
      Statement messages =
          prepare(part, "SELECT id, topic_id, timestamp FROM messages ORDER BY timestamp, id");
      while (step(part, messages.get())) {
        const std::int64_t topic_id = sqlite3_column_int64(messages.get(), 1);
        const auto topic = topic_of_id_[part].find(topic_id);
        if (topic == topic_of_id_[part].end()) {
          throw InputError(files_[part].string(), 0, "messages.topic_id",
                           fmt::format("{} is not in the topics table", topic_id));
        }
        BagMessage message;
        message.topic = topic->second;
        message.log_time_ns = sqlite3_column_int64(messages.get(), 2);
        message.ref = {.part = part,
                       .at = static_cast<std::uint64_t>(sqlite3_column_int64(messages.get(), 0)),
                       .size = 0};
        if (topic_wanted[message.topic]) {
          read_blob(part, message.ref.at, data_prefix > 0 ? data_prefix : kWholeMessage, data);
          message.data = data;
        }
        on_message(message);
      }
    }
    return {.writer = "rosbag2 (sqlite3)", .truncated_at = std::nullopt};
  }

  std::string read(const BagMessageRef& ref) const override {
    // One connection per file, used by one thread at a time.
    const std::lock_guard lock(mutex_);
    if (ref.part >= files_.size()) throw std::out_of_range("Ros2SqliteBag::read: no such file");
    std::string data;
    read_blob(ref.part, ref.at, kWholeMessage, data);
    return data;
  }

 private:
  Database open(const std::filesystem::path& file) const {
    sqlite3* raw = nullptr;
    const int code = sqlite3_open_v2(file.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    Database database(raw);
    if (code != SQLITE_OK) {
      throw InputError(file.string(),
                       fmt::format("cannot open it as SQLite: {}", sqlite3_errstr(code)));
    }
    return database;
  }

  Statement prepare(std::size_t part, const char* sql) const {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(databases_[part].get(), sql, -1, &raw, nullptr) != SQLITE_OK) {
      throw InputError(files_[part].string(),
                       fmt::format("not a rosbag2 sqlite3 file ({}): {}", sql,
                                   sqlite3_errmsg(databases_[part].get())));
    }
    return Statement(raw);
  }

  // True while a row is there; an InputError for a corrupt file.
  bool step(std::size_t part, sqlite3_stmt* statement) const {
    const int code = sqlite3_step(statement);
    if (code == SQLITE_ROW) return true;
    if (code == SQLITE_DONE) return false;
    throw InputError(files_[part].string(),
                     fmt::format("cannot read it: {}", sqlite3_errmsg(databases_[part].get())));
  }

  static constexpr std::size_t kWholeMessage = std::numeric_limits<int>::max();

  // The first `count` bytes of a message's data (all of it when shorter) into `out`, through
  // SQLite's incremental blob I/O: the scan reads a LiDAR sweep's header while its megabytes stay
  // on disk, and a read copies the data once, into `out`.
  void read_blob(std::size_t part, std::uint64_t row, std::size_t count, std::string& out) const {
    sqlite3_blob* raw = nullptr;
    if (sqlite3_blob_open(databases_[part].get(), "main", "messages", "data",
                          static_cast<sqlite3_int64>(row), 0, &raw) != SQLITE_OK) {
      sqlite3_blob_close(raw);
      throw InputError(files_[part].string(), fmt::format("cannot read message {}: {}", row,
                                                          sqlite3_errmsg(databases_[part].get())));
    }
    const auto size = std::min(static_cast<std::size_t>(sqlite3_blob_bytes(raw)), count);
    out.resize(size);
    const int code = sqlite3_blob_read(raw, out.data(), static_cast<int>(size), 0);
    sqlite3_blob_close(raw);
    if (code != SQLITE_OK) {
      throw InputError(files_[part].string(),
                       fmt::format("cannot read message {}: {}", row, sqlite3_errstr(code)));
    }
  }

  static std::string text(sqlite3_stmt* statement, int column) {
    const unsigned char* value = sqlite3_column_text(statement, column);
    return value == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(value));
  }

  std::vector<std::filesystem::path> files_;
  std::vector<Database> databases_;
  std::vector<std::map<std::int64_t, std::size_t>> topic_of_id_;
  mutable std::mutex mutex_;
};

// metadata.yaml's storage and files.
struct Ros2Metadata {
  std::string storage;
  std::vector<std::filesystem::path> files;
};

Ros2Metadata read_metadata(const std::filesystem::path& folder) {
  const std::filesystem::path file = folder / "metadata.yaml";
  const std::string source = file.string();
  const YAML::Node root = load_yaml_mapping(read_text_file(file), source);
  const YAML::Node information = root["rosbag2_bagfile_information"];
  if (!information.IsMap()) {
    throw InputError(source, 0, "rosbag2_bagfile_information",
                     "missing: not a rosbag2 metadata file");
  }
  Ros2Metadata metadata;
  try {
    metadata.storage = information["storage_identifier"].as<std::string>("sqlite3");
    const YAML::Node paths = information["relative_file_paths"];
    if (!paths.IsSequence() || paths.size() == 0) {
      throw InputError(source, yaml_line(paths), "relative_file_paths", "lists no files");
    }
    for (const YAML::Node& path : paths) metadata.files.push_back(folder / path.as<std::string>());
  } catch (const YAML::Exception& error) {
    throw InputError(source, yaml_line(error.mark), "rosbag2_bagfile_information", error.msg);
  }
  for (const std::filesystem::path& path : metadata.files) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
      throw InputError(source, 0, "relative_file_paths",
                       fmt::format("{} is not there", path.string()));
    }
  }
  return metadata;
}

}  // namespace

std::unique_ptr<BagFile> open_ros2_bag(const std::filesystem::path& path,
                                       const BagOptions& options) {
  std::error_code error;
  if (!std::filesystem::is_directory(path, error)) {
    return std::make_unique<Ros2SqliteBag>(path, std::vector{path});
  }
  const Ros2Metadata metadata = read_metadata(path);
  if (metadata.storage == "mcap") {
    if (metadata.files.size() != 1) {
      throw InputError(
          (path / "metadata.yaml").string(), 0, "relative_file_paths",
          fmt::format("names {} MCAP files; give x2car one of them", metadata.files.size()));
    }
    return open_mcap_bag(metadata.files.front(), options);
  }
  if (metadata.storage != "sqlite3") {
    throw InputError(
        (path / "metadata.yaml").string(), 0, "storage_identifier",
        fmt::format("'{}': x2car reads the sqlite3 and mcap storages", metadata.storage));
  }
  return std::make_unique<Ros2SqliteBag>(path, metadata.files);
}

}  // namespace x2car::io
