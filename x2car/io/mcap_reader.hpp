// MCAP files (mcap.dev, format version 0), read as a stream (issue 17 item 1): the records in file
// order up to the data end, chunks decompressed one at a time (lz4 frames through liblz4, zstd
// through libzstd, or none), never the whole file in memory. Schemas, channels and messages go to
// the handlers; indexes, attachments, metadata and statistics are passed over, and so is the
// summary section (it repeats the schemas and channels for readers that seek). A chunk's CRC is
// checked when it is decompressed whole. Messages come in file order: a writer may log them out of
// time order, and the caller sorts what it keeps.
//
// A reader that needs only the first bytes of some channels' messages now (a LiDAR's sweep
// headers, to order the sweeps before it reads them again in parallel) says so
// (McapReadOptions::data_prefix): a chunk followed by its message indexes is then decompressed
// only as far as those prefixes reach, and the other messages are delivered from the indexes
// (channel and log time, no data). Compressed sweeps are so decompressed once, when they are read,
// not twice.
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
  std::string_view data;  // valid during the handler call only; see data_size
  // The data's whole size: data.size(), or more when only a prefix was read (data_prefix), or when
  // the message was known from a message index alone (data empty).
  std::uint64_t data_size = 0;
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
  // > 0: of a message on a channel for which `wants_data` is true, only this many first bytes are
  // needed now, and of the other channels' messages none (0: every message whole). Takes effect
  // per chunk, where the chunk's message indexes follow it and name only channels already seen.
  std::size_t data_prefix = 0;
  std::function<bool(std::uint16_t channel_id)> wants_data = {};  // of a channel; unset: all
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

// The data of one message that read_mcap delivered, read again from the message's chunk_offset,
// data_offset and data_size: its chunk decompressed as far as the message ends (its CRC checked
// when that is the whole chunk). The last chunk decompressed is kept per thread, so that messages
// read in file order from one chunk decompress it once. Throws InputError.
std::string read_mcap_message(const std::filesystem::path& path, std::uint64_t chunk_offset,
                              std::uint64_t data_offset, std::uint64_t size);

}  // namespace x2car::io
