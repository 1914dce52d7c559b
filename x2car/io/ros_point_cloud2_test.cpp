#include "x2car/io/ros_point_cloud2.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;

// A PointCloud2 message by hand, in ROS 1's packed encoding or little-endian CDR.
struct FieldSpec {
  std::string name;
  std::uint32_t offset;
  std::uint8_t datatype;
};

class CloudBytes {
 public:
  explicit CloudBytes(RosEncoding encoding) : encoding_(encoding) {
    if (encoding_ == RosEncoding::kCdr) bytes_ = std::string("\0\1\0\0", 4);
  }
  std::string message(std::int64_t stamp_ns, std::uint32_t height, std::uint32_t width,
                      const std::vector<FieldSpec>& fields, std::uint32_t point_step,
                      const std::string& data, bool big_endian = false) {
    if (encoding_ == RosEncoding::kRos1) put32(0);  // seq
    put32(static_cast<std::uint32_t>(stamp_ns / 1'000'000'000));
    put32(static_cast<std::uint32_t>(stamp_ns % 1'000'000'000));
    text("lidar");
    put32(height);
    put32(width);
    put32(static_cast<std::uint32_t>(fields.size()));
    for (const FieldSpec& field : fields) {
      text(field.name);
      put32(field.offset);
      bytes_ += static_cast<char>(field.datatype);
      put32(1);
    }
    bytes_ += static_cast<char>(big_endian ? 1 : 0);
    put32(point_step);
    put32(point_step * width);
    put32(static_cast<std::uint32_t>(data.size()));
    bytes_ += data;
    bytes_ += '\0';  // is_dense
    return bytes_;
  }

 private:
  void align4() {
    if (encoding_ == RosEncoding::kCdr) {
      while ((bytes_.size() - 4) % 4 != 0) bytes_ += '\0';
    }
  }
  void put32(std::uint32_t value) {
    align4();
    for (int i = 0; i < 4; ++i) bytes_ += static_cast<char>((value >> (8 * i)) & 0xff);
  }
  void text(const std::string& value) {
    const bool cdr = encoding_ == RosEncoding::kCdr;
    put32(static_cast<std::uint32_t>(value.size() + (cdr ? 1 : 0)));
    bytes_ += value;
    if (cdr) bytes_ += '\0';
  }
  RosEncoding encoding_;
  std::string bytes_;
};

template <typename T>
void put_at(std::string& data, std::size_t at, T value, bool big_endian = false) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (big_endian) std::reverse(raw, raw + sizeof(T));
  std::memcpy(data.data() + at, raw, sizeof(T));
}

constexpr std::int64_t kStampNs = 1'541'234'567'100'000'000LL;

TEST(DecodePointCloud2, ReadsX2carsOwnLayoutInBothEncodings) {
  for (const RosEncoding encoding : {RosEncoding::kRos1, RosEncoding::kCdr}) {
    std::string data(2 * 22, '\0');
    for (int i = 0; i < 2; ++i) {
      put_at<float>(data, 22 * i + 0, 1.5f + i);
      put_at<float>(data, 22 * i + 4, -2.0f);
      put_at<float>(data, 22 * i + 8, std::nanf(""));
      put_at<float>(data, 22 * i + 12, 40.0f);
      put_at<std::uint16_t>(data, 22 * i + 16, static_cast<std::uint16_t>(7 + i));
      put_at<float>(data, 22 * i + 18, 0.05f * static_cast<float>(i));
    }
    const std::string bytes = CloudBytes(encoding).message(kStampNs, 1, 2,
                                                           {{"x", 0, 7},
                                                            {"y", 4, 7},
                                                            {"z", 8, 7},
                                                            {"intensity", 12, 7},
                                                            {"ring", 16, 4},
                                                            {"t", 18, 7}},
                                                           22, data);
    const StampedPointCloud decoded = decode_point_cloud2(bytes, encoding, "m");
    EXPECT_EQ(decoded.header.stamp_ns, kStampNs);
    EXPECT_EQ(decoded.header.frame_id, "lidar");
    ASSERT_EQ(decoded.cloud.points.size(), 2U);
    EXPECT_TRUE(decoded.cloud.has_intensity && decoded.cloud.has_ring && decoded.cloud.has_time);
    EXPECT_EQ(decoded.cloud.points[1].x, 2.5f);
    EXPECT_TRUE(std::isnan(decoded.cloud.points[0].z));
    EXPECT_EQ(decoded.cloud.points[1].ring, 8);
    EXPECT_EQ(decoded.cloud.points[1].t, 0.05f);
    EXPECT_EQ(read_point_cloud2_header(bytes, encoding, "m").stamp_ns, kStampNs);
  }
}

// Ouster: uint32 `t` in nanoseconds after the stamp, padding, an organised cloud (2 x 1).
TEST(DecodePointCloud2, ReadsOustersNanosecondOffsetsRowByRow) {
  std::string data(2 * 48, '\0');
  for (int i = 0; i < 2; ++i) {
    put_at<float>(data, 48 * i + 0, 3.0f);
    put_at<float>(data, 48 * i + 16, 12.0f);
    put_at<std::uint32_t>(data, 48 * i + 20, 25'000'000U * static_cast<std::uint32_t>(i + 1));
    put_at<std::uint16_t>(data, 48 * i + 26, static_cast<std::uint16_t>(i));
  }
  const std::string bytes = CloudBytes(RosEncoding::kCdr)
                                .message(kStampNs, 2, 1,
                                         {{"x", 0, 7},
                                          {"y", 4, 7},
                                          {"z", 8, 7},
                                          {"intensity", 16, 7},
                                          {"t", 20, 6},
                                          {"reflectivity", 24, 4},
                                          {"ring", 26, 4}},
                                         48, data);
  const PointCloud cloud = decode_point_cloud2(bytes, RosEncoding::kCdr, "m").cloud;
  ASSERT_EQ(cloud.points.size(), 2U);
  EXPECT_FLOAT_EQ(cloud.points[0].t, 0.025f);
  EXPECT_FLOAT_EQ(cloud.points[1].t, 0.050f);
  EXPECT_EQ(cloud.points[1].ring, 1);
  EXPECT_EQ(cloud.points[1].intensity, 12.0f);
}

// Absolute float64 `timestamp`: Hesai's seconds and Livox's nanoseconds, both relative to the
// stamp after decoding.
TEST(DecodePointCloud2, TakesAbsoluteTimestampsInSecondsOrNanoseconds) {
  const double stamp_s = static_cast<double>(kStampNs) * 1e-9;
  for (const double scale : {1.0, 1e9}) {
    std::string data(26, '\0');
    put_at<float>(data, 0, 1.0f);
    put_at<double>(data, 18, (stamp_s + 0.04) * scale);
    const std::string bytes =
        CloudBytes(RosEncoding::kRos1)
            .message(kStampNs, 1, 1,
                     {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}, {"line", 17, 2}, {"timestamp", 18, 8}},
                     26, data);
    const PointCloud cloud = decode_point_cloud2(bytes, RosEncoding::kRos1, "m").cloud;
    EXPECT_NEAR(cloud.points[0].t, 0.04, 1e-5) << scale;
    EXPECT_TRUE(cloud.has_ring);
  }
}

// Near a clock's zero (a simulation's), nanoseconds still read as nanoseconds: one point at the
// stamp itself, another 50 ms later.
TEST(DecodePointCloud2, TellsNanosecondsFromSecondsNearAClocksZero) {
  std::string data(2 * 20, '\0');
  put_at<double>(data, 12, 0.0);
  put_at<double>(data, 32, 5e7);
  const std::string bytes =
      CloudBytes(RosEncoding::kCdr)
          .message(0, 1, 2, {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}, {"timestamp", 12, 8}}, 20,
                   data);
  const PointCloud cloud = decode_point_cloud2(bytes, RosEncoding::kCdr, "m").cloud;
  EXPECT_FLOAT_EQ(cloud.points[0].t, 0.0f);
  EXPECT_FLOAT_EQ(cloud.points[1].t, 0.05f);
}

TEST(DecodePointCloud2, ReadsFloat64CoordinatesAndBigEndianData) {
  std::string data(24, '\0');
  put_at<double>(data, 0, -7.25, true);
  put_at<double>(data, 8, 0.5, true);
  put_at<double>(data, 16, 1.0, true);
  const std::string bytes = CloudBytes(RosEncoding::kCdr)
                                .message(kStampNs, 1, 1, {{"x", 0, 8}, {"y", 8, 8}, {"z", 16, 8}},
                                         24, data, /*big_endian=*/true);
  const PointCloud cloud = decode_point_cloud2(bytes, RosEncoding::kCdr, "m").cloud;
  EXPECT_EQ(cloud.points[0].x, -7.25f);
  EXPECT_EQ(cloud.points[0].y, 0.5f);
  EXPECT_FALSE(cloud.has_time);
  EXPECT_FALSE(cloud.has_ring);
}

TEST(DecodePointCloud2, RejectsBrokenLayoutsNamingTheField) {
  const auto error_of = [](const std::vector<FieldSpec>& fields, std::uint32_t point_step,
                           std::size_t data_size) {
    const std::string bytes =
        CloudBytes(RosEncoding::kRos1)
            .message(kStampNs, 1, 2, fields, point_step, std::string(data_size, '\0'));
    try {
      decode_point_cloud2(bytes, RosEncoding::kRos1, "run.bag (/points message 4)");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::vector<FieldSpec> xyz = {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}};
  EXPECT_THAT(error_of({{"x", 0, 7}, {"y", 4, 7}}, 12, 24), HasSubstr("no field z"));
  EXPECT_THAT(error_of(xyz, 8, 16), HasSubstr("fields.z"));
  EXPECT_THAT(error_of(xyz, 12, 20), HasSubstr("data"));
  EXPECT_THAT(error_of({{"x", 0, 5}, {"y", 4, 7}, {"z", 8, 7}}, 12, 24), HasSubstr("fields.x"));
  EXPECT_THAT(error_of({{"x", 0, 7}, {"y", 4, 9}, {"z", 8, 7}}, 12, 24), HasSubstr("datatype 9"));
  EXPECT_THAT(error_of(xyz, 12, 20), HasSubstr("/points message 4"));
  // An absolute timestamp nowhere near the header's stamp.
  std::string data(2 * 20, '\0');
  put_at<double>(data, 12, 5.0);
  put_at<double>(data, 32, 5.0);
  const std::string bytes =
      CloudBytes(RosEncoding::kRos1)
          .message(kStampNs, 1, 2, {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}, {"timestamp", 12, 8}},
                   20, data);
  EXPECT_THROW(decode_point_cloud2(bytes, RosEncoding::kRos1, "m"), InputError);
}

}  // namespace
}  // namespace x2car::io
