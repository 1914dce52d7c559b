// MCAP files (mcap.dev, format version 0), read as a stream (issue 17 item 1): the records in file
// order up to the data end, chunks decompressed one at a time (lz4 frames through liblz4, zstd
// through libzstd, or none), never the whole file in memory. Schemas, channels and messages go to
// the handlers; indexes, attachments, metadata and statistics are passed over, and so is the
// summary section (it repeats the schemas and channels for readers that seek). A chunk's CRC is
// checked when it has one. Messages come in file order: a writer may log them out of time order,
// and the caller sorts what it keeps.
//
// Errors name the file and the byte offset of the record: a file that does not start with the
// magic, a record longer than the rest of the file, a chunk that does not decompress to its size,
// an unknown compression. A file cut short (a recording that did not close) is an error too,
// unless `allow_truncated`: the messages before the cut were delivered, and the result says where
// it ends.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace x2car::io {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      // e.g. "sensor_msgs/msg/PointCloud2"
  std::string encoding;  // e.g. "ros2msg", "ros1msg", "jsonschema"
  std::string data;      // the message definition
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // e.g. "cdr", "ros1", "json"
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::string_view data;  // valid during the handler call only
  // Where the data lies, for read_mcap_message: the file offset of the chunk record holding it
  // (0: not in a chunk) and the data's offset in the chunk's records or, outside a chunk, the file.
  std::uint64_t chunk_offset = 0;
  std::uint64_t data_offset = 0;
};

struct McapHandlers {
  std::function<void(const McapSchema&)> on_schema;
  std::function<void(const McapChannel&)> on_channel;
  std::function<void(const McapMessage&)> on_message;
};

struct McapReadOptions {
  bool allow_truncated = false;  // a file cut short ends the stream instead of an error
};

struct McapReadEnd {
  std::string profile;  // the header's, e.g. "ros2"
  std::string library;  // the writer the header names
  // Set when the file was cut short (allow_truncated): the byte offset of the record that could
  // not be read whole.
  std::optional<std::uint64_t> truncated_at;
};

// True when the file starts with the MCAP magic.
bool looks_like_mcap(const std::filesystem::path& path);

// Streams the file's records to the handlers (unset handlers are skipped). Throws InputError.
McapReadEnd read_mcap(const std::filesystem::path& path, const McapHandlers& handlers,
                      const McapReadOptions& options = {});

// The data of one message that read_mcap delivered, read again: its chunk decompressed anew (its
// CRC was checked by read_mcap) from the message's chunk_offset, data_offset and the data's size.
// Throws InputError.
std::string read_mcap_message(const std::filesystem::path& path, std::uint64_t chunk_offset,
                              std::uint64_t data_offset, std::uint64_t size);

}  // namespace x2car::io
