#include "x2car/io/mcap_reader.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace x2car::io
