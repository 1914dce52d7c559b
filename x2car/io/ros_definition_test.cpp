#include "x2car/io/ros_definition.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

// ROS 1 bytes by hand: little-endian, packed.
struct Ros1Bytes {
  std::string bytes;
  template <typename T>
  Ros1Bytes& put(T value) {
    const auto raw = std::bit_cast<std::array<char, sizeof(T)>>(value);
    bytes.append(raw.data(), raw.size());
    return *this;
  }
  Ros1Bytes& text(const std::string& value) {
    put<std::uint32_t>(static_cast<std::uint32_t>(value.size()));
    bytes += value;
    return *this;
  }
};

constexpr const char* kDefinition =
    "Header header\n"
    "Inner[2] pair      # a fixed array of a type of this package\n"
    "uint8 GOOD=3\n"
    "float32[] values\n"
    "string<=8 name\n"
    "float64 latitude\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "uint32 seq\ntime stamp\nstring frame_id\n"
    "================================================================================\n"
    "MSG: pkg/Inner\n"
    "int16 a\nuint64 b\n";

TEST(RosDefinition, ReadsLeavesThroughNestedTypesAndArrays) {
  const RosDefinition definition("pkg/Outer", kDefinition, "def");
  Ros1Bytes m;
  m.put<std::uint32_t>(9).put<std::uint32_t>(12).put<std::uint32_t>(300).text("gps");
  m.put<std::int16_t>(-4).put<std::uint64_t>(7).put<std::int16_t>(5).put<std::uint64_t>(8);
  m.put<std::uint32_t>(2).put<float>(0.5f).put<float>(1.5f);
  m.text("abc").put<double>(48.1);
  const auto values = definition.read_numbers(m.bytes, RosEncoding::kRos1, "m",
                                              {"header.stamp.sec", "header.stamp.nsec", "pair[0].a",
                                               "pair[1].b", "values[1]", "latitude", "no_such"});
  EXPECT_EQ(values.at("header.stamp.sec"), 12.0);
  EXPECT_EQ(values.at("header.stamp.nsec"), 300.0);
  EXPECT_EQ(values.at("pair[0].a"), -4.0);
  EXPECT_EQ(values.at("pair[1].b"), 8.0);
  EXPECT_EQ(values.at("values[1]"), 1.5);
  EXPECT_EQ(values.at("latitude"), 48.1);
  EXPECT_FALSE(values.contains("no_such"));
  EXPECT_THROW(definition.read_numbers(m.bytes.substr(0, 20), RosEncoding::kRos1, "m", {}),
               InputError);
}

TEST(RosDefinition, RejectsUndefinedTypesAndSelfNesting) {
  EXPECT_THROW(RosDefinition("pkg/A", "Missing m\n", "def"), InputError);
  EXPECT_THROW(RosDefinition("pkg/A", "justaword\n", "def"), InputError);
  const RosDefinition self("pkg/A", "A inner\n", "def");
  EXPECT_THROW(self.read_numbers(std::string(64, '\0'), RosEncoding::kRos1, "m", {}), InputError);
}

}  // namespace
}  // namespace x2car::io
