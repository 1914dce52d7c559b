#include "x2car/io/mcap_reader.hpp"

#include <fmt/format.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <memory>
#include <set>
#include <vector>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

constexpr std::array<unsigned char, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

// Record opcodes (mcap.dev/spec).
enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kDataEnd = 0x0F,
};

// Little-endian fields of one record's content, each read checked against its end.
class Fields {
 public:
  Fields(std::string_view bytes, const std::string& file, std::uint64_t offset)
      : bytes_(bytes), file_(file), offset_(offset) {}

  template <typename Integer>
  Integer integer(const char* field) {
    need(sizeof(Integer), field);
    Integer value = 0;
    for (std::size_t i = 0; i < sizeof(Integer); ++i) {
      value |= static_cast<Integer>(static_cast<unsigned char>(bytes_[at_ + i])) << (8 * i);
    }
    at_ += sizeof(Integer);
    return value;
  }

  std::string_view bytes(std::uint64_t count, const char* field) {
    need(count, field);
    const std::string_view part = bytes_.substr(at_, count);
    at_ += count;
    return part;
  }

  std::string string(const char* field) {
    const auto length = integer<std::uint32_t>(field);
    return std::string(bytes(length, field));
  }

  std::string_view rest() const { return bytes_.substr(at_); }

 private:
  void need(std::uint64_t count, const char* field) const {
    if (count > bytes_.size() - at_) {
      throw InputError(file_, 0, field,
                       fmt::format("the record at byte {} ends inside this field", offset_));
    }
  }

  std::string_view bytes_;
  const std::string& file_;
  std::uint64_t offset_;
  std::size_t at_ = 0;
};

McapSchema parse_schema(Fields fields) {
  McapSchema schema;
  schema.id = fields.integer<std::uint16_t>("schema.id");
  schema.name = fields.string("schema.name");
  schema.encoding = fields.string("schema.encoding");
  const auto length = fields.integer<std::uint32_t>("schema.data");
  schema.data = std::string(fields.bytes(length, "schema.data"));
  return schema;
}

McapChannel parse_channel(Fields fields) {
  McapChannel channel;
  channel.id = fields.integer<std::uint16_t>("channel.id");
  channel.schema_id = fields.integer<std::uint16_t>("channel.schema_id");
  channel.topic = fields.string("channel.topic");
  channel.message_encoding = fields.string("channel.message_encoding");
  const auto map_bytes = fields.integer<std::uint32_t>("channel.metadata");
  const std::string_view map = fields.bytes(map_bytes, "channel.metadata");
  Fields entries(map, "", 0);
  while (!entries.rest().empty()) {
    std::string key = entries.string("channel.metadata");
    channel.metadata[std::move(key)] = entries.string("channel.metadata");
  }
  return channel;
}

McapMessage parse_message(Fields fields) {
  McapMessage message;
  message.channel_id = fields.integer<std::uint16_t>("message.channel_id");
  message.sequence = fields.integer<std::uint32_t>("message.sequence");
  message.log_time_ns = fields.integer<std::uint64_t>("message.log_time");
  message.publish_time_ns = fields.integer<std::uint64_t>("message.publish_time");
  message.data = fields.rest();
  message.data_size = message.data.size();
  return message;
}

// Schemas, channels and messages of a run of records (a chunk's content); others passed over.
void dispatch_records(std::string_view records, const McapHandlers& handlers,
                      const std::string& file, std::uint64_t chunk_offset) {
  Fields fields(records, file, chunk_offset);
  while (!fields.rest().empty()) {
    const auto opcode = fields.integer<std::uint8_t>("chunk record");
    const auto length = fields.integer<std::uint64_t>("chunk record");
    const std::string_view content = fields.bytes(length, "chunk record");
    const Fields inner(content, file, chunk_offset);
    if (opcode == kSchema && handlers.on_schema) handlers.on_schema(parse_schema(inner));
    if (opcode == kChannel && handlers.on_channel) handlers.on_channel(parse_channel(inner));
    if (opcode == kMessage && handlers.on_message) {
      McapMessage message = parse_message(inner);
      message.chunk_offset = chunk_offset;
      message.data_offset = static_cast<std::uint64_t>(message.data.data() - records.data());
      handlers.on_message(message);
    }
  }
}

// A chunk's records, decompressed from the front as far as asked: the whole chunk for a reader
// that dispatches every record, its first kilobytes for one that needs only some messages'
// headers (McapReadOptions::data_prefix). An uncompressed chunk is a view of the record itself.
class ChunkRecords {
 public:
  // `content`: the chunk record's content. `buffer` receives the decompressed bytes; it must
  // outlive the views returned.
  ChunkRecords(std::string_view content, const std::string& file, std::uint64_t offset,
               std::vector<char>& buffer)
      : file_(file), offset_(offset), buffer_(buffer) {
    Fields fields(content, file, offset);
    fields.integer<std::uint64_t>("chunk.message_start_time");
    fields.integer<std::uint64_t>("chunk.message_end_time");
    size_ = fields.integer<std::uint64_t>("chunk.uncompressed_size");
    crc_ = fields.integer<std::uint32_t>("chunk.uncompressed_crc");
    compression_ = fields.string("chunk.compression");
    const auto records_size = fields.integer<std::uint64_t>("chunk.records");
    records_ = fields.bytes(records_size, "chunk.records");
    if (compression_.empty()) {
      if (size_ != records_.size()) {
        throw InputError(file, fmt::format("the uncompressed chunk at byte {} holds {} bytes, not "
                                           "the {} it declares",
                                           offset, records_.size(), size_));
      }
      ready_ = size_;
      return;
    }
    if (compression_ != "zstd" && compression_ != "lz4") {
      throw InputError(file, 0, "chunk.compression",
                       fmt::format("the chunk at byte {} is compressed with '{}'; x2car reads "
                                   "lz4, zstd and uncompressed chunks",
                                   offset, compression_));
    }
    // A declared size past any plausible chunk (writers cut chunks at a few megabytes; one huge
    // message may make one larger) is a corrupt length, not a reason to allocate.
    constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;
    if (size_ > kMaxChunkBytes) {
      throw InputError(file, fmt::format("the chunk at byte {} declares {} bytes uncompressed; "
                                         "x2car reads chunks of up to {} bytes",
                                         offset, size_, kMaxChunkBytes));
    }
    if (compression_ == "zstd") {
      const unsigned long long framed = ZSTD_getFrameContentSize(records_.data(), records_.size());
      if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed != size_) {
        throw InputError(file, fmt::format("the zstd chunk at byte {} holds {} bytes, not the {} "
                                           "it declares",
                                           offset, framed, size_));
      }
    }
    buffer_.resize(size_);
  }

  ~ChunkRecords() {
    if (zstd_ != nullptr) ZSTD_freeDCtx(zstd_);
    if (lz4_ != nullptr) LZ4F_freeDecompressionContext(lz4_);
  }
  ChunkRecords(const ChunkRecords&) = delete;
  ChunkRecords& operator=(const ChunkRecords&) = delete;

  std::uint64_t size() const { return size_; }

  // At least the first min(bytes, size()) decompressed bytes (all that is ready).
  std::string_view prefix(std::uint64_t bytes) {
    const std::uint64_t target = std::min(bytes, size_);
    if (ready_ < target) {
      if (compression_ == "zstd") {
        decompress_zstd(target);
      } else {
        decompress_lz4(target);
      }
      if (ready_ < target) {
        throw InputError(file_, fmt::format("the {} chunk at byte {} gives {} bytes, not the {} "
                                            "it declares",
                                            compression_, offset_, ready_, size_));
      }
    }
    return compression_.empty() ? records_ : std::string_view(buffer_.data(), ready_);
  }

  // Everything, its CRC checked when the chunk has one.
  std::string_view all() {
    const std::string_view plain = prefix(size_);
    if (crc_ != 0 && !crc_checked_) {
      const auto computed = static_cast<std::uint32_t>(::crc32(
          0L, reinterpret_cast<const Bytef*>(plain.data()), static_cast<uInt>(plain.size())));
      if (computed != crc_) {
        throw InputError(file_, fmt::format("the chunk at byte {} fails its CRC (0x{:08x}, "
                                            "expected 0x{:08x}): the file is corrupt",
                                            offset_, computed, crc_));
      }
      crc_checked_ = true;
    }
    return plain;
  }

 private:
  void decompress_zstd(std::uint64_t target) {
    if (ready_ == 0 && target == size_) {
      // The whole frame at once: faster than the stream, which copies through its window.
      const std::size_t written =
          ZSTD_decompress(buffer_.data(), buffer_.size(), records_.data(), records_.size());
      if (ZSTD_isError(written) != 0 || written != size_) {
        throw InputError(file_, fmt::format("the zstd chunk at byte {} does not decompress to its "
                                            "{} bytes{}",
                                            offset_, size_,
                                            ZSTD_isError(written) != 0
                                                ? std::string(": ") + ZSTD_getErrorName(written)
                                                : std::string()));
      }
      ready_ = size_;
      return;
    }
    if (zstd_ == nullptr) {
      zstd_ = ZSTD_createDCtx();
      if (zstd_ == nullptr) throw std::runtime_error("zstd: cannot create a decompression context");
    }
    ZSTD_inBuffer in{records_.data(), records_.size(), zstd_read_};
    ZSTD_outBuffer out{buffer_.data(), target, ready_};
    while (out.pos < target) {
      const std::size_t written = out.pos;
      const std::size_t read = in.pos;
      const std::size_t status = ZSTD_decompressStream(zstd_, &out, &in);
      if (ZSTD_isError(status) != 0) {
        throw InputError(file_, fmt::format("the zstd chunk at byte {} does not decompress: {}",
                                            offset_, ZSTD_getErrorName(status)));
      }
      if (status == 0 || (out.pos == written && in.pos == read)) break;  // its end, or stuck
    }
    ready_ = out.pos;
    zstd_read_ = in.pos;
  }

  void decompress_lz4(std::uint64_t target) {
    if (lz4_ == nullptr && LZ4F_isError(LZ4F_createDecompressionContext(&lz4_, LZ4F_VERSION))) {
      throw std::runtime_error("lz4: cannot create a decompression context");
    }
    while (ready_ < target && lz4_read_ < records_.size()) {
      std::size_t out_size = target - ready_;
      std::size_t in_size = records_.size() - lz4_read_;
      const std::size_t status = LZ4F_decompress(lz4_, buffer_.data() + ready_, &out_size,
                                                 records_.data() + lz4_read_, &in_size, nullptr);
      if (LZ4F_isError(status)) {
        throw InputError(file_, fmt::format("the lz4 chunk at byte {} does not decompress: {}",
                                            offset_, LZ4F_getErrorName(status)));
      }
      ready_ += out_size;
      lz4_read_ += in_size;
      if (status == 0 || (out_size == 0 && in_size == 0)) break;
    }
  }

  const std::string& file_;
  std::uint64_t offset_;
  std::vector<char>& buffer_;
  std::string_view records_;
  std::string compression_;
  std::uint64_t size_ = 0;
  std::uint32_t crc_ = 0;
  std::uint64_t ready_ = 0;  // decompressed bytes in buffer_
  bool crc_checked_ = false;
  ZSTD_DCtx* zstd_ = nullptr;
  std::size_t zstd_read_ = 0;
  LZ4F_dctx* lz4_ = nullptr;
  std::size_t lz4_read_ = 0;
};

// One message index (opcode 0x07) of the chunk before it: its channel's messages, by log time and
// offset in the chunk's records.
struct IndexedMessage {
  std::uint16_t channel_id = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t offset = 0;
};

void parse_message_index(Fields fields, std::vector<IndexedMessage>& out) {
  const auto channel = fields.integer<std::uint16_t>("message_index.channel_id");
  const auto bytes = fields.integer<std::uint32_t>("message_index.records");
  Fields entries(fields.bytes(bytes, "message_index.records"), "", 0);
  while (!entries.rest().empty()) {
    IndexedMessage message{.channel_id = channel};
    message.log_time_ns = entries.integer<std::uint64_t>("message_index.records");
    message.offset = entries.integer<std::uint64_t>("message_index.records");
    out.push_back(message);
  }
}

// The summary section's schemas and channels (the footer's summary_start; mcap.dev/spec), for a
// reader that passes over parts of chunks and so may not see the records there. Empty when the
// file has no summary, or no footer (a file cut short).
struct Summary {
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
};

Summary read_summary(std::ifstream& stream, const std::string& file, std::uint64_t file_size) {
  Summary summary;
  constexpr std::uint64_t kFooterRecord = 1 + 8 + 20;  // opcode, length, the footer's fields
  if (file_size < 2 * kMagic.size() + kFooterRecord) return summary;
  std::array<char, kFooterRecord + kMagic.size()> tail{};
  stream.seekg(static_cast<std::streamoff>(file_size - tail.size()));
  if (!stream.read(tail.data(), tail.size()) || static_cast<std::uint8_t>(tail[0]) != kFooter ||
      std::memcmp(tail.data() + kFooterRecord, kMagic.data(), kMagic.size()) != 0) {
    stream.clear();
    return summary;
  }
  Fields footer(std::string_view(tail.data() + 9, 20), file, file_size - tail.size());
  const auto summary_start = footer.integer<std::uint64_t>("footer.summary_start");
  const std::uint64_t summary_end = file_size - tail.size();
  if (summary_start == 0 || summary_start < kMagic.size() || summary_start > summary_end) {
    return summary;
  }
  std::vector<char> bytes(summary_end - summary_start);
  stream.seekg(static_cast<std::streamoff>(summary_start));
  if (!stream.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) {
    stream.clear();
    return summary;
  }
  try {
    Fields records(std::string_view(bytes.data(), bytes.size()), file, summary_start);
    while (!records.rest().empty()) {
      const auto opcode = records.integer<std::uint8_t>("summary record");
      const auto length = records.integer<std::uint64_t>("summary record");
      const Fields content(records.bytes(length, "summary record"), file, summary_start);
      if (opcode == kSchema) {
        McapSchema schema = parse_schema(content);
        summary.schemas[schema.id] = std::move(schema);
      } else if (opcode == kChannel) {
        McapChannel channel = parse_channel(content);
        summary.channels[channel.id] = std::move(channel);
      }
    }
  } catch (const InputError&) {
    return {};  // the stream reads every chunk whole then, and judges the file by its records
  }
  return summary;
}

}  // namespace

bool looks_like_mcap(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::array<char, kMagic.size()> start{};
  return stream.read(start.data(), start.size()) &&
         std::memcmp(start.data(), kMagic.data(), kMagic.size()) == 0;
}

namespace {

// A chunk's messages from its message indexes (McapReadOptions::data_prefix): the wanted channels'
// first data_prefix bytes decompressed, the others delivered without data. Every channel's schema
// and channel record is delivered from the summary before its first message, since the passed-over
// part of a chunk may hold them.
class IndexedChunkReader {
 public:
  IndexedChunkReader(const McapHandlers& handlers, const McapReadOptions& options,
                     const Summary& summary, const std::string& file)
      : handlers_(handlers), options_(options), summary_(summary), file_(file) {}

  void on_schema(const McapSchema& schema) {
    delivered_schemas_.insert(schema.id);
    if (handlers_.on_schema) handlers_.on_schema(schema);
  }
  void on_channel(const McapChannel& channel) {
    delivered_channels_.insert(channel.id);
    if (handlers_.on_channel) handlers_.on_channel(channel);
  }

  void dispatch(ChunkRecords& chunk, std::vector<IndexedMessage>& index,
                std::uint64_t chunk_offset) {
    std::ranges::sort(index, {}, &IndexedMessage::offset);
    constexpr std::uint64_t kRecordHead = 1 + 8;           // opcode, length
    constexpr std::uint64_t kMessageHead = 2 + 4 + 8 + 8;  // channel, sequence, two times
    for (const IndexedMessage& entry : index) {
      deliver_channel(entry.channel_id);
      McapMessage message;
      message.channel_id = entry.channel_id;
      message.log_time_ns = entry.log_time_ns;
      message.chunk_offset = chunk_offset;
      if (!options_.wants_data || options_.wants_data(entry.channel_id)) {
        const auto nowhere = [&] {
          return InputError(file_, fmt::format("the message index of the chunk at byte {} points "
                                               "at byte {} of it, where no message is",
                                               chunk_offset, entry.offset));
        };
        if (entry.offset > chunk.size() ||
            chunk.size() - entry.offset < kRecordHead + kMessageHead) {
          throw nowhere();
        }
        const std::uint64_t start = entry.offset + kRecordHead;
        Fields head(chunk.prefix(start + kMessageHead).substr(entry.offset), file_, chunk_offset);
        const auto opcode = head.integer<std::uint8_t>("message_index.offset");
        const auto length = head.integer<std::uint64_t>("message_index.offset");
        if (opcode != kMessage || length < kMessageHead || length > chunk.size() - start) {
          throw nowhere();
        }
        const std::uint64_t kept =
            std::min<std::uint64_t>(length - kMessageHead, options_.data_prefix);
        const std::string_view records = chunk.prefix(start + kMessageHead + kept);
        message =
            parse_message(Fields(records.substr(start, kMessageHead + kept), file_, chunk_offset));
        message.data_size = length - kMessageHead;
        message.chunk_offset = chunk_offset;
        message.data_offset = start + kMessageHead;
      }
      if (handlers_.on_message) handlers_.on_message(message);
    }
  }

  // The summary's schemas and channels that no record delivered (a channel without messages).
  void deliver_the_rest() {
    for (const auto& [id, channel] : summary_.channels) deliver_channel(id);
  }

 private:
  void deliver_channel(std::uint16_t id) {
    if (delivered_channels_.contains(id)) return;
    const auto channel = summary_.channels.find(id);
    if (channel == summary_.channels.end()) return;  // the handler says the file lacks it
    const auto schema = summary_.schemas.find(channel->second.schema_id);
    if (schema != summary_.schemas.end() && !delivered_schemas_.contains(schema->first)) {
      on_schema(schema->second);
    }
    on_channel(channel->second);
  }

  const McapHandlers& handlers_;
  const McapReadOptions& options_;
  const Summary& summary_;
  const std::string& file_;
  std::set<std::uint16_t> delivered_schemas_;
  std::set<std::uint16_t> delivered_channels_;
};

}  // namespace

McapReadEnd read_mcap(const std::filesystem::path& path, const McapHandlers& handlers,
                      const McapReadOptions& options) {
  const std::string file = path.string();
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(file, "cannot open the file");
  std::error_code error;
  const std::uintmax_t file_size = std::filesystem::file_size(path, error);
  if (error) throw InputError(file, "cannot read the file's size: " + error.message());
  std::array<char, kMagic.size()> magic{};
  if (!stream.read(magic.data(), magic.size()) ||
      std::memcmp(magic.data(), kMagic.data(), kMagic.size()) != 0) {
    throw InputError(file, file_size == 0 ? "the file is empty" : "not an MCAP file (no magic)");
  }
  // Reading parts of chunks needs every channel known beforehand: from the summary.
  Summary summary;
  if (options.data_prefix > 0) {
    summary = read_summary(stream, file, file_size);
    stream.seekg(static_cast<std::streamoff>(kMagic.size()));
  }
  const bool indexed = !summary.channels.empty();
  IndexedChunkReader indexed_reader(handlers, options, summary, file);
  McapHandlers stream_handlers = handlers;
  if (indexed) {
    stream_handlers.on_schema = [&](const McapSchema& schema) { indexed_reader.on_schema(schema); };
    stream_handlers.on_channel = [&](const McapChannel& channel) {
      indexed_reader.on_channel(channel);
    };
  }

  McapReadEnd end;
  std::vector<char> content;
  std::vector<char> chunk_buffer;
  // A chunk waits for the message indexes after it before its messages are delivered.
  std::vector<char> pending;
  std::optional<std::uint64_t> pending_offset;
  std::vector<IndexedMessage> index;
  const auto flush = [&] {
    if (!pending_offset) return;
    const std::uint64_t chunk_offset = *pending_offset;
    pending_offset.reset();
    ChunkRecords chunk(std::string_view(pending.data(), pending.size()), file, chunk_offset,
                       chunk_buffer);
    if (indexed && !index.empty()) {
      indexed_reader.dispatch(chunk, index, chunk_offset);
    } else {
      dispatch_records(chunk.all(), stream_handlers, file, chunk_offset);
    }
  };
  std::uint64_t offset = kMagic.size();
  const auto cut_short = [&](const std::string& what) {
    if (!options.allow_truncated) {
      throw InputError(file, fmt::format("the file ends at byte {} inside {} (a recording that "
                                         "did not close?); --allow-truncated reads what comes "
                                         "before",
                                         file_size, what));
    }
    flush();
    end.truncated_at = offset;
    return end;
  };
  while (true) {
    std::array<char, 9> head{};
    if (!stream.read(head.data(), head.size())) {
      if (stream.gcount() == 0 && offset == file_size) {
        return cut_short(
            fmt::format("the record stream after byte {} (no data end, no footer)", offset));
      }
      return cut_short(fmt::format("the record at byte {}", offset));
    }
    const auto opcode = static_cast<std::uint8_t>(head[0]);
    std::uint64_t length = 0;
    for (int i = 0; i < 8; ++i) {
      length |= static_cast<std::uint64_t>(static_cast<unsigned char>(head[1 + i])) << (8 * i);
    }
    if (length > file_size - offset - head.size()) {
      return cut_short(fmt::format("the record at byte {} (it claims {} bytes, {} are left)",
                                   offset, length, file_size - offset - head.size()));
    }
    content.resize(length);
    if (!stream.read(content.data(), static_cast<std::streamsize>(length))) {
      return cut_short(fmt::format("the record at byte {}", offset));
    }
    const std::string_view bytes(content.data(), content.size());
    const Fields fields(bytes, file, offset);
    if (opcode == kMessageIndex && pending_offset) {
      if (indexed) parse_message_index(fields, index);
      offset += head.size() + length;
      continue;
    }
    flush();
    switch (opcode) {
      case kHeader: {
        Fields header = fields;
        end.profile = header.string("header.profile");
        end.library = header.string("header.library");
        break;
      }
      case kSchema:
        if (stream_handlers.on_schema) stream_handlers.on_schema(parse_schema(fields));
        break;
      case kChannel:
        if (stream_handlers.on_channel) stream_handlers.on_channel(parse_channel(fields));
        break;
      case kMessage:
        if (handlers.on_message) {
          McapMessage message = parse_message(fields);
          message.data_offset =
              offset + head.size() + static_cast<std::uint64_t>(message.data.data() - bytes.data());
          handlers.on_message(message);
        }
        break;
      case kChunk:
        std::swap(content, pending);
        pending_offset = offset;
        index.clear();
        break;
      case kDataEnd:
      case kFooter:
        // The summary section after it repeats schemas and channels for readers that seek; the
        // stream has had everything.
        if (indexed) indexed_reader.deliver_the_rest();
        return end;
      default:
        break;  // indexes, attachments, metadata, statistics
    }
    offset += head.size() + length;
  }
}

std::string read_mcap_message(const std::filesystem::path& path, std::uint64_t chunk_offset,
                              std::uint64_t data_offset, std::uint64_t size) {
  const std::string file = path.string();
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(file, "cannot open the file");
  const auto read_at = [&](std::uint64_t at, std::uint64_t count, std::vector<char>& into,
                           const char* what) {
    into.resize(count);
    stream.seekg(static_cast<std::streamoff>(at));
    if (!stream.read(into.data(), static_cast<std::streamsize>(count))) {
      throw InputError(
          file, fmt::format("cannot read {} at byte {} again (the file changed?)", what, at));
    }
    return std::string_view(into.data(), into.size());
  };
  // Per thread, reused: a LiDAR's sweeps are read again one by one, a few megabytes each, and
  // fresh buffers cost page faults and zeroing each time; the last chunk stays decompressed for
  // the next message in it.
  struct LastChunk {
    std::string file;
    std::uint64_t offset = 0;
    std::vector<char> content;
    std::vector<char> buffer;
    std::unique_ptr<ChunkRecords> records;
  };
  thread_local LastChunk last;
  const auto read_message_at = [&](std::uint64_t at) {
    std::string message(size, '\0');
    stream.seekg(static_cast<std::streamoff>(at));
    if (!stream.read(message.data(), static_cast<std::streamsize>(size))) {
      throw InputError(
          file, fmt::format("cannot read a message at byte {} again (the file changed?)", at));
    }
    return message;
  };
  if (chunk_offset == 0) return read_message_at(data_offset);
  const auto check_holds = [&](std::uint64_t records_size) {
    if (data_offset > records_size || size > records_size - data_offset) {
      last.records.reset();
      throw InputError(file, fmt::format("the chunk at byte {} does not hold the message at {} "
                                         "(the file changed?)",
                                         chunk_offset, data_offset));
    }
  };
  if (!last.records || last.offset != chunk_offset || last.file != file) {
    last.records.reset();
    // The chunk record's head: its opcode and length, the chunk's two times, size, CRC and the
    // compression's length; an uncompressed chunk's records' length and its records follow.
    constexpr std::uint64_t kPlainRecordsStart = 1 + 8 + 8 + 8 + 8 + 4 + 4 + 8;
    std::vector<char> head;
    Fields fields(read_at(chunk_offset, kPlainRecordsStart, head, "a chunk's header"), file,
                  chunk_offset);
    const auto opcode = fields.integer<std::uint8_t>("chunk");
    const auto length = fields.integer<std::uint64_t>("chunk");
    if (opcode != kChunk || length > (std::uint64_t{1} << 31)) {
      throw InputError(file, fmt::format("no chunk at byte {} (the file changed?)", chunk_offset));
    }
    fields.bytes(8 + 8 + 8 + 4, "chunk");  // times, size, CRC
    if (fields.integer<std::uint32_t>("chunk.compression") == 0) {
      // An uncompressed chunk's message is read alone, straight from the file.
      check_holds(fields.integer<std::uint64_t>("chunk.records"));
      return read_message_at(chunk_offset + kPlainRecordsStart + data_offset);
    }
    last.file = file;
    last.offset = chunk_offset;
    const std::string_view chunk = read_at(chunk_offset + 9, length, last.content, "a chunk");
    last.records = std::make_unique<ChunkRecords>(chunk, last.file, chunk_offset, last.buffer);
  }
  ChunkRecords& records = *last.records;
  check_holds(records.size());
  const std::uint64_t end = data_offset + size;
  try {
    const std::string_view plain = end == records.size() ? records.all() : records.prefix(end);
    return std::string(plain.substr(data_offset, size));
  } catch (...) {
    last.records.reset();  // a chunk that failed is decompressed anew, and fails anew
    throw;
  }
}

}  // namespace x2car::io
