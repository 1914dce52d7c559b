#include "x2car/io/ros_message.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

// CDR bytes by hand: little- or big-endian, each value aligned to its size after the header.
struct Cdr {
  std::string bytes;
  bool big_endian = false;
  explicit Cdr(bool big = false) : big_endian(big) {
    bytes = std::string("\0\0\0\0", 4);
    bytes[1] = big ? 0 : 1;
  }
  void align(std::size_t size) {
    while ((bytes.size() - 4) % size != 0) bytes += '\0';
  }
  template <typename Unsigned>
  Cdr& put(Unsigned value) {
    align(sizeof(Unsigned));
    for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
      const std::size_t shift = big_endian ? 8 * (sizeof(Unsigned) - 1 - i) : 8 * i;
      bytes += static_cast<char>((value >> shift) & 0xff);
    }
    return *this;
  }
  Cdr& text(const std::string& value) {
    put<std::uint32_t>(static_cast<std::uint32_t>(value.size() + 1));
    bytes += value;
    bytes += '\0';
    return *this;
  }
};

TEST(RosMessageReader, ReadsAlignedFieldsInBothByteOrders) {
  for (const bool big : {false, true}) {
    Cdr cdr(big);
    cdr.put<std::uint32_t>(std::bit_cast<std::uint32_t>(std::int32_t{-5}));
    cdr.put<std::uint32_t>(7).text("map").put<std::uint8_t>(3);
    cdr.put<std::uint64_t>(std::bit_cast<std::uint64_t>(1.25));  // aligned to 8 after the byte
    RosMessageReader reader(cdr.bytes, RosEncoding::kCdr, "message");
    EXPECT_EQ(reader.int32("sec"), -5) << big;
    EXPECT_EQ(reader.uint32("nanosec"), 7U);
    EXPECT_EQ(reader.string("frame_id"), "map");
    EXPECT_EQ(reader.uint8("flag"), 3);
    EXPECT_EQ(reader.float64("x"), 1.25);
  }
}

TEST(RosMessageReader, ErrorsNameTheField) {
  Cdr cdr;
  cdr.put<std::uint32_t>(1);
  RosMessageReader reader(cdr.bytes, RosEncoding::kCdr, "run.mcap (/odom message 3)");
  reader.uint32("header.stamp.sec");
  try {
    reader.float64("pose.pose.position.x");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "pose.pose.position.x");
    EXPECT_NE(std::string(error.what()).find("/odom message 3"), std::string::npos);
  }
  EXPECT_THROW(RosMessageReader(std::string("\x01\x02", 2), RosEncoding::kCdr, "m"), InputError);
  EXPECT_THROW(RosMessageReader(std::string("\x00\x07\x00\x00", 4), RosEncoding::kCdr, "m"),
               InputError);
}

// ROS 1: packed little-endian, strings without a NUL, Header with its seq.
TEST(RosMessageReader, ReadsRos1PackedFields) {
  std::string bytes;
  const auto put32 = [&](std::uint32_t value) {
    for (int i = 0; i < 4; ++i) bytes += static_cast<char>((value >> (8 * i)) & 0xff);
  };
  put32(17);         // seq
  put32(12);         // stamp.sec
  put32(300000000);  // stamp.nsec
  put32(5);
  bytes += "lidar";  // frame_id, no NUL
  bytes += '\x01';   // a bool, then a float64 right after it (no alignment)
  const auto value = std::bit_cast<std::uint64_t>(-2.5);
  for (int i = 0; i < 8; ++i) bytes += static_cast<char>((value >> (8 * i)) & 0xff);
  RosMessageReader reader(bytes, RosEncoding::kRos1, "run.bag (/points message 1)");
  const RosHeader header = reader.header();
  EXPECT_EQ(header.stamp_ns, 12'300'000'000LL);
  EXPECT_EQ(header.frame_id, "lidar");
  EXPECT_TRUE(reader.boolean("is_dense"));
  EXPECT_EQ(reader.float64("x"), -2.5);
  EXPECT_THROW(reader.uint8("past the end"), InputError);
}

TEST(RosMessageReader, RejectsANanosecondPartOfASecondOrMore) {
  Cdr cdr;
  cdr.put<std::uint32_t>(1).put<std::uint32_t>(1'000'000'000U);
  RosMessageReader reader(cdr.bytes, RosEncoding::kCdr, "m");
  EXPECT_THROW(reader.time_ns("header.stamp"), InputError);
}

}  // namespace
}  // namespace x2car::io
