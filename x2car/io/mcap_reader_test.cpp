#include "x2car/io/mcap_reader.hpp"

#include <gtest/gtest.h>
#include <lz4frame.h>
#include <zstd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

// MCAP bytes by hand (the spec's little-endian records), for the cases an independent writer
// cannot make: malformed fields. tests/bags checks files the MCAP project's own writer made.
struct Bytes {
  std::string data;
  template <typename Integer>
  Bytes& integer(Integer value) {
    for (std::size_t i = 0; i < sizeof(Integer); ++i) {
      data += static_cast<char>((static_cast<std::uint64_t>(value) >> (8 * i)) & 0xff);
    }
    return *this;
  }
  Bytes& string(const std::string& text) {
    integer<std::uint32_t>(static_cast<std::uint32_t>(text.size()));
    data += text;
    return *this;
  }
  Bytes& record(std::uint8_t opcode, const Bytes& content) {
    integer<std::uint8_t>(opcode);
    integer<std::uint64_t>(content.data.size());
    data += content.data;
    return *this;
  }
};

std::filesystem::path write(const std::string& name, const std::string& bytes) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

Bytes with_magic() {
  Bytes file;
  file.data = std::string("\x89MCAP0\r\n", 8);
  file.record(0x01, Bytes().string("ros2").string("hand"));
  return file;
}

Bytes channel_record(const std::string& topic) {
  Bytes metadata;
  metadata.string("qos").string("reliable");
  Bytes channel;
  channel.integer<std::uint16_t>(1).integer<std::uint16_t>(7).string(topic).string("cdr");
  channel.integer<std::uint32_t>(static_cast<std::uint32_t>(metadata.data.size()));
  channel.data += metadata.data;
  return channel;
}

TEST(McapReader, ReadsSchemasChannelsAndMessagesInFileOrder) {
  Bytes file = with_magic();
  file.record(0x03, Bytes()
                        .integer<std::uint16_t>(7)
                        .string("sensor_msgs/msg/Imu")
                        .string("ros2msg")
                        .string("float64 x"));
  file.record(0x04, channel_record("/imu"));
  for (const std::uint64_t time : {200, 100}) {
    Bytes message;
    message.integer<std::uint16_t>(1).integer<std::uint32_t>(3).integer<std::uint64_t>(time);
    message.integer<std::uint64_t>(time).data += "abc";
    file.record(0x05, message);
  }
  file.record(0x0F, Bytes().integer<std::uint32_t>(0));
  std::vector<std::string> seen;
  McapHandlers handlers;
  handlers.on_schema = [&](const McapSchema& schema) {
    seen.push_back(schema.name + " " + schema.encoding + " " + schema.data);
  };
  handlers.on_channel = [&](const McapChannel& channel) {
    seen.push_back(channel.topic + " " + channel.metadata.at("qos"));
  };
  handlers.on_message = [&](const McapMessage& message) {
    seen.push_back(std::to_string(message.log_time_ns) + " " + std::string(message.data));
  };
  const McapReadEnd end = read_mcap(write("hand.mcap", file.data), handlers);
  EXPECT_EQ(end.profile, "ros2");
  EXPECT_FALSE(end.truncated_at);
  EXPECT_EQ(seen, (std::vector<std::string>{"sensor_msgs/msg/Imu ros2msg float64 x",
                                            "/imu reliable", "200 abc", "100 abc"}));
}

// A field longer than its record: InputError naming the field and the record's byte.
TEST(McapReader, AFieldPastItsRecordIsAnError) {
  Bytes file = with_magic();
  Bytes channel = channel_record("/imu");
  channel.data[4] = 100;  // the topic's length byte: 100, past the record
  file.record(0x04, channel);
  const auto path = write("bad_field.mcap", file.data);
  try {
    read_mcap(path, {.on_schema = {}, .on_channel = [](const McapChannel&) {}, .on_message = {}});
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("channel.topic"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("record at byte 33"), std::string::npos)
        << error.what();
  }
  // A chunk in an unknown compression names it.
  Bytes chunked = with_magic();
  Bytes chunk;
  chunk.integer<std::uint64_t>(0).integer<std::uint64_t>(0).integer<std::uint64_t>(3);
  chunk.integer<std::uint32_t>(0).string("brotli").integer<std::uint64_t>(3).data += "xyz";
  chunked.record(0x06, chunk);
  EXPECT_THROW(read_mcap(write("brotli.mcap", chunked.data), {}), InputError);
  EXPECT_FALSE(looks_like_mcap(write("text.mcap", "not an mcap file")));
}

// A chunk of three messages (zstd), its message indexes, and a summary naming the two channels: the
// file a LiDAR's scan reads only the sweeps' first bytes of.
struct IndexedFile {
  std::string bytes;
  std::string first, second, third;  // the messages' data, in file order
};

Bytes message_record(std::uint16_t channel, std::uint64_t time, const std::string& data) {
  Bytes message;
  message.integer<std::uint16_t>(channel).integer<std::uint32_t>(0).integer<std::uint64_t>(time);
  message.integer<std::uint64_t>(time).data += data;
  return message;
}

Bytes channel_with_id(std::uint16_t id, const std::string& topic) {
  Bytes channel = channel_record(topic);
  channel.data[0] = static_cast<char>(id);
  return channel;
}

IndexedFile indexed_file(bool with_summary, std::uint64_t bad_offset = 0,
                         bool broken_summary = false, const std::string& compression = "zstd") {
  IndexedFile out;
  out.first = std::string(100, 'a');
  out.second = std::string(200000, 'b');  // past a 64 KiB lz4 block
  for (int i = 0; i < 1000; ++i) out.third += static_cast<char>('0' + i % 10);
  const Bytes schema = Bytes()
                           .integer<std::uint16_t>(7)
                           .string("sensor_msgs/msg/PointCloud2")
                           .string("ros2msg")
                           .string("");
  Bytes records;
  records.record(0x03, schema).record(0x04, channel_with_id(1, "/points"));
  records.record(0x04, channel_with_id(2, "/other"));
  std::vector<std::uint64_t> offsets;
  for (const auto& [channel, data] : std::vector<std::pair<std::uint16_t, std::string>>{
           {1, out.first}, {2, out.second}, {1, out.third}}) {
    offsets.push_back(records.data.size());
    records.record(0x05, message_record(channel, 100 + offsets.size(), data));
  }
  std::string compressed;
  if (compression == "zstd") {
    compressed.resize(ZSTD_compressBound(records.data.size()));
    compressed.resize(ZSTD_compress(compressed.data(), compressed.size(), records.data.data(),
                                    records.data.size(), 3));
  } else {  // lz4 in the library's default 64 KiB blocks
    compressed.resize(LZ4F_compressFrameBound(records.data.size(), nullptr));
    compressed.resize(LZ4F_compressFrame(compressed.data(), compressed.size(), records.data.data(),
                                         records.data.size(), nullptr));
  }
  Bytes file = with_magic();
  Bytes chunk;
  chunk.integer<std::uint64_t>(101).integer<std::uint64_t>(103);
  chunk.integer<std::uint64_t>(records.data.size()).integer<std::uint32_t>(0).string(compression);
  chunk.integer<std::uint64_t>(compressed.size()).data += compressed;
  file.record(0x06, chunk);
  Bytes index1;
  index1.integer<std::uint16_t>(1).integer<std::uint32_t>(32);
  index1.integer<std::uint64_t>(101).integer<std::uint64_t>(bad_offset != 0 ? bad_offset
                                                                            : offsets[0]);
  index1.integer<std::uint64_t>(103).integer<std::uint64_t>(offsets[2]);
  Bytes index2;
  index2.integer<std::uint16_t>(2).integer<std::uint32_t>(16);
  index2.integer<std::uint64_t>(102).integer<std::uint64_t>(offsets[1]);
  file.record(0x07, index1).record(0x07, index2);
  file.record(0x0F, Bytes().integer<std::uint32_t>(0));
  std::uint64_t summary_start = 0;
  if (with_summary) {
    summary_start = file.data.size();
    file.record(0x03, schema).record(0x04, channel_with_id(1, "/points"));
    file.record(0x04, channel_with_id(2, "/other"));
    if (broken_summary) file.record(0x04, Bytes().integer<std::uint16_t>(3));
  }
  file.record(0x02, Bytes()
                        .integer<std::uint64_t>(summary_start)
                        .integer<std::uint64_t>(0)
                        .integer<std::uint32_t>(0));
  file.data += std::string("\x89MCAP0\r\n", 8);
  out.bytes = file.data;
  return out;
}

struct Seen {
  std::vector<std::string> channels;
  std::vector<McapMessage> messages;
  std::vector<std::string> data;
};

Seen read_prefix(const std::filesystem::path& path, std::size_t prefix) {
  Seen seen;
  McapHandlers handlers;
  handlers.on_channel = [&](const McapChannel& channel) { seen.channels.push_back(channel.topic); };
  handlers.on_message = [&](const McapMessage& message) {
    seen.messages.push_back(message);
    seen.data.emplace_back(message.data);
  };
  read_mcap(path, handlers,
            {.data_prefix = prefix, .wants_data = [](std::uint16_t id) { return id == 1; }});
  return seen;
}

// With a data prefix, a chunk is decompressed only as far as the wanted messages' prefixes: their
// first bytes come with their whole size, the other channel's message without data, and each reads
// back whole by its offsets.
class McapPrefix : public ::testing::TestWithParam<std::string> {};

TEST_P(McapPrefix, ReadsOnlyTheWantedPrefixesOfAnIndexedChunk) {
  const IndexedFile file = indexed_file(true, 0, false, GetParam());
  const auto path = write("indexed_" + GetParam() + ".mcap", file.bytes);
  const Seen seen = read_prefix(path, 10);
  EXPECT_EQ(seen.channels, (std::vector<std::string>{"/points", "/other"}));
  ASSERT_EQ(seen.messages.size(), 3u);
  EXPECT_EQ(seen.data,
            (std::vector<std::string>{file.first.substr(0, 10), "", file.third.substr(0, 10)}));
  EXPECT_EQ(seen.messages[0].data_size, 100u);
  EXPECT_EQ(seen.messages[1].log_time_ns, 102u);
  EXPECT_EQ(seen.messages[2].data_size, 1000u);
  for (const int i : {2, 0, 2}) {  // out of order, and the same chunk twice (the thread's cache)
    const McapMessage& message = seen.messages[i];
    EXPECT_EQ(read_mcap_message(path, message.chunk_offset, message.data_offset, message.data_size),
              i == 0 ? file.first : file.third);
  }
  // A prefix longer than a message gives it whole.
  EXPECT_EQ(read_prefix(path, 5000).data[0], file.first);
  // Without a summary the chunk is read whole (its records may declare channels the index does
  // not show); the other channel's message then comes with its data.
  const Seen whole = read_prefix(write("unindexed.mcap", indexed_file(false).bytes), 10);
  EXPECT_EQ(whole.data[1], file.second);
  EXPECT_EQ(whole.messages[0].data_size, 100u);
  // A summary that does not parse is passed over the same way: the chunks' own records decide.
  const Seen broken =
      read_prefix(write("broken_summary.mcap", indexed_file(true, 0, true).bytes), 10);
  EXPECT_EQ(broken.data[1], file.second);
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapPrefix, ::testing::Values("zstd", "lz4"));

TEST(McapReader, AnIndexPointingAtNoMessageIsAnError) {
  const auto path = write("bad_index.mcap", indexed_file(true, 3).bytes);
  try {
    read_prefix(path, 10);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("points at byte 3 of it, where no message is"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace x2car::io
