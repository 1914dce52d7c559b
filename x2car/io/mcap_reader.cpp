#include "x2car/io/mcap_reader.hpp"

#include <fmt/format.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <array>
#include <cstring>
#include <fstream>
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

void decompress_lz4(std::string_view compressed, std::vector<char>& out, const std::string& file,
                    std::uint64_t offset) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) {
    throw std::runtime_error("lz4: cannot create a decompression context");
  }
  std::size_t written = 0;
  std::size_t read = 0;
  std::size_t status = 1;
  while (status != 0 && read < compressed.size() && written < out.size()) {
    std::size_t out_size = out.size() - written;
    std::size_t in_size = compressed.size() - read;
    status = LZ4F_decompress(context, out.data() + written, &out_size, compressed.data() + read,
                             &in_size, nullptr);
    if (LZ4F_isError(status)) {
      LZ4F_freeDecompressionContext(context);
      throw InputError(file, fmt::format("the lz4 chunk at byte {} does not decompress: {}", offset,
                                         LZ4F_getErrorName(status)));
    }
    written += out_size;
    read += in_size;
    if (out_size == 0 && in_size == 0) break;
  }
  LZ4F_freeDecompressionContext(context);
  if (written != out.size()) {
    throw InputError(file, fmt::format("the lz4 chunk at byte {} gives {} bytes, not the {} it "
                                       "declares",
                                       offset, written, out.size()));
  }
}

void decompress_zstd(std::string_view compressed, std::vector<char>& out, const std::string& file,
                     std::uint64_t offset) {
  const std::size_t written =
      ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(written) != 0 || written != out.size()) {
    throw InputError(file, fmt::format("the zstd chunk at byte {} does not decompress to its {} "
                                       "bytes{}",
                                       offset, out.size(),
                                       ZSTD_isError(written) != 0
                                           ? std::string(": ") + ZSTD_getErrorName(written)
                                           : std::string()));
  }
}

// A chunk record's content: its records, decompressed into `buffer` when compressed; its CRC
// checked when `check_crc` (a chunk read again was checked when the stream read it).
std::string_view chunk_records(std::string_view content, const std::string& file,
                               std::uint64_t offset, std::vector<char>& buffer,
                               bool check_crc = true) {
  Fields fields(content, file, offset);
  fields.integer<std::uint64_t>("chunk.message_start_time");
  fields.integer<std::uint64_t>("chunk.message_end_time");
  const auto size = fields.integer<std::uint64_t>("chunk.uncompressed_size");
  const auto crc = fields.integer<std::uint32_t>("chunk.uncompressed_crc");
  const std::string compression = fields.string("chunk.compression");
  const auto records_size = fields.integer<std::uint64_t>("chunk.records");
  const std::string_view records = fields.bytes(records_size, "chunk.records");
  std::string_view plain = records;
  if (!compression.empty()) {
    // A declared size past any plausible chunk (writers cut chunks at a few megabytes; one huge
    // message may make one larger) is a corrupt length, not a reason to allocate.
    constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;
    if (size > kMaxChunkBytes) {
      throw InputError(file, fmt::format("the chunk at byte {} declares {} bytes uncompressed; "
                                         "x2car reads chunks of up to {} bytes",
                                         offset, size, kMaxChunkBytes));
    }
    if (compression == "zstd") {
      const unsigned long long framed = ZSTD_getFrameContentSize(records.data(), records.size());
      if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed != size) {
        throw InputError(file, fmt::format("the zstd chunk at byte {} holds {} bytes, not the {} "
                                           "it declares",
                                           offset, framed, size));
      }
    }
    buffer.resize(size);
    if (compression == "zstd") {
      decompress_zstd(records, buffer, file, offset);
    } else if (compression == "lz4") {
      decompress_lz4(records, buffer, file, offset);
    } else {
      throw InputError(file, 0, "chunk.compression",
                       fmt::format("the chunk at byte {} is compressed with '{}'; x2car reads "
                                   "lz4, zstd and uncompressed chunks",
                                   offset, compression));
    }
    plain = std::string_view(buffer.data(), buffer.size());
  } else if (size != records.size()) {
    throw InputError(file, fmt::format("the uncompressed chunk at byte {} holds {} bytes, not the "
                                       "{} it declares",
                                       offset, records.size(), size));
  }
  if (crc != 0 && check_crc) {
    const auto computed = static_cast<std::uint32_t>(
        ::crc32(0L, reinterpret_cast<const Bytef*>(plain.data()), static_cast<uInt>(plain.size())));
    if (computed != crc) {
      throw InputError(file, fmt::format("the chunk at byte {} fails its CRC (0x{:08x}, expected "
                                         "0x{:08x}): the file is corrupt",
                                         offset, computed, crc));
    }
  }
  return plain;
}

}  // namespace

bool looks_like_mcap(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::array<char, kMagic.size()> start{};
  return stream.read(start.data(), start.size()) &&
         std::memcmp(start.data(), kMagic.data(), kMagic.size()) == 0;
}

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
  McapReadEnd end;
  std::vector<char> content;
  std::vector<char> chunk_buffer;
  std::uint64_t offset = kMagic.size();
  const auto cut_short = [&](const std::string& what) {
    if (!options.allow_truncated) {
      throw InputError(file, fmt::format("the file ends at byte {} inside {} (a recording that "
                                         "did not close?); --allow-truncated reads what comes "
                                         "before",
                                         file_size, what));
    }
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
    switch (opcode) {
      case kHeader: {
        Fields header = fields;
        end.profile = header.string("header.profile");
        end.library = header.string("header.library");
        break;
      }
      case kSchema:
        if (handlers.on_schema) handlers.on_schema(parse_schema(fields));
        break;
      case kChannel:
        if (handlers.on_channel) handlers.on_channel(parse_channel(fields));
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
        dispatch_records(chunk_records(bytes, file, offset, chunk_buffer), handlers, file, offset);
        break;
      case kDataEnd:
      case kFooter:
        // The summary section after it repeats schemas and channels for readers that seek; the
        // stream has had everything.
        return end;
      default:
        break;  // indexes, attachments, metadata, statistics, data end
    }
    offset += head.size() + length;
  }
}

std::string read_mcap_message(const std::filesystem::path& path, std::uint64_t chunk_offset,
                              std::uint64_t data_offset, std::uint64_t size) {
  const std::string file = path.string();
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(file, "cannot open the file");
  // Per thread, reused: a LiDAR's sweeps are read again one by one, a few megabytes each, and
  // fresh buffers cost page faults and zeroing each time.
  thread_local std::vector<char> content;
  thread_local std::vector<char> buffer;
  const auto read_at = [&](std::uint64_t at, std::uint64_t count, const char* what) {
    content.resize(count);
    stream.seekg(static_cast<std::streamoff>(at));
    if (!stream.read(content.data(), static_cast<std::streamsize>(count))) {
      throw InputError(
          file, fmt::format("cannot read {} at byte {} again (the file changed?)", what, at));
    }
    return std::string_view(content.data(), content.size());
  };
  if (chunk_offset == 0) return std::string(read_at(data_offset, size, "a message"));
  const std::string head(read_at(chunk_offset, 9, "a chunk"));
  std::uint64_t length = 0;
  for (int i = 0; i < 8; ++i) {
    length |= static_cast<std::uint64_t>(static_cast<unsigned char>(head[1 + i])) << (8 * i);
  }
  if (static_cast<std::uint8_t>(head[0]) != kChunk || length > (std::uint64_t{1} << 31)) {
    throw InputError(file, fmt::format("no chunk at byte {} (the file changed?)", chunk_offset));
  }
  const std::string_view chunk = read_at(chunk_offset + 9, length, "a chunk");
  const std::string_view records =
      chunk_records(chunk, file, chunk_offset, buffer, /*check_crc=*/false);
  if (data_offset > records.size() || size > records.size() - data_offset) {
    throw InputError(file, fmt::format("the chunk at byte {} does not hold the message at {} "
                                       "(the file changed?)",
                                       chunk_offset, data_offset));
  }
  return std::string(records.substr(data_offset, size));
}

}  // namespace x2car::io
