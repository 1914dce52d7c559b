#include "x2car/io/pcd.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

PointCloud sample_cloud() {
  PointCloud cloud;
  cloud.has_intensity = cloud.has_ring = cloud.has_time = true;
  for (int i = 0; i < 500; ++i) {
    const float f = static_cast<float>(i);
    cloud.points.push_back({0.37f * f - 20.0f, std::sin(f) * 15.0f, -1.7f + 0.001f * f,
                            std::fmod(7.0f * f, 255.0f), static_cast<std::uint16_t>(i % 64),
                            0.0001f * f});
  }
  cloud.points[3].x = std::numeric_limits<float>::quiet_NaN();  // a beam without a return
  return cloud;
}

void expect_same_points(const PointCloud& actual, const PointCloud& expected) {
  ASSERT_EQ(actual.points.size(), expected.points.size());
  for (std::size_t i = 0; i < actual.points.size(); ++i) {
    const LidarPoint& a = actual.points[i];
    const LidarPoint& e = expected.points[i];
    if (std::isnan(e.x)) {
      EXPECT_TRUE(std::isnan(a.x)) << i;
    } else {
      EXPECT_EQ(a.x, e.x) << i;
    }
    EXPECT_EQ(a.y, e.y) << i;
    EXPECT_EQ(a.z, e.z) << i;
    EXPECT_EQ(a.intensity, e.intensity) << i;
    EXPECT_EQ(a.ring, e.ring) << i;
    EXPECT_EQ(a.t, e.t) << i;
  }
}

class PcdRoundTrip : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(PcdRoundTrip, ReadsBackEveryPointExactlyAndKeepsNaN) {
  const PointCloud cloud = sample_cloud();
  const PointCloud read = parse_pcd(format_pcd(cloud, GetParam()), "sweep.pcd");
  EXPECT_TRUE(read.has_intensity && read.has_ring && read.has_time);
  EXPECT_EQ(read.time_base, 0.0);
  expect_same_points(read, cloud);
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, PcdRoundTrip,
                         ::testing::Values(PcdEncoding::kAscii, PcdEncoding::kBinary,
                                           PcdEncoding::kBinaryCompressed));

TEST(Pcd, WritesTheDocumentedBinaryLayout) {
  PointCloud cloud;
  cloud.points.push_back({1.0f, 2.0f, 3.0f, 40.0f, 7, 0.05f});
  const std::string bytes = format_pcd(cloud);
  EXPECT_THAT(bytes, HasSubstr("FIELDS x y z intensity ring t\nSIZE 4 4 4 4 2 4\n"
                               "TYPE F F F F U F\nCOUNT 1 1 1 1 1 1\nWIDTH 1\nHEIGHT 1\n"));
  const std::size_t data = bytes.find("DATA binary\n") + 12;
  ASSERT_EQ(bytes.size() - data, 22u);
  std::uint16_t ring = 0;
  std::memcpy(&ring, bytes.data() + data + 16, 2);
  EXPECT_EQ(ring, 7);
}

TEST(Pcd, EmptyCloudRoundTrips) {
  for (const auto encoding :
       {PcdEncoding::kAscii, PcdEncoding::kBinary, PcdEncoding::kBinaryCompressed}) {
    EXPECT_TRUE(parse_pcd(format_pcd(PointCloud{}, encoding), "empty.pcd").points.empty());
  }
}

// Ouster-like: padding field with COUNT 4, ring after t, t in uint32 nanoseconds, doubles.
TEST(Pcd, ReadsOtherFieldOrdersSizesAndTypes) {
  const std::string text =
      "# from a driver\n"
      "VERSION 0.7\n"
      "FIELDS x y z _ t ring intensity\n"
      "SIZE 8 8 4 1 4 1 2\n"
      "TYPE F F F U U U U\n"
      "COUNT 1 1 1 4 1 1 1\n"
      "WIDTH 2\n"
      "HEIGHT 1\n"
      "POINTS 2\n"
      "DATA ascii\n"
      "1.5 -2 0.25 0 0 0 0 50000000 3 200\n"
      "nan nan nan 0 0 0 0 99000000 63 0\n";
  const PointCloud cloud = parse_pcd(text, "ouster.pcd");
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[0].x, 1.5f);
  EXPECT_EQ(cloud.points[0].y, -2.0f);
  EXPECT_FLOAT_EQ(cloud.points[0].t, 0.05f);  // nanoseconds of an integer field
  EXPECT_EQ(cloud.points[0].ring, 3);
  EXPECT_EQ(cloud.points[0].intensity, 200.0f);
  EXPECT_TRUE(std::isnan(cloud.points[1].z));
  EXPECT_EQ(cloud.points[1].ring, 63);
}

TEST(Pcd, AbsoluteTimestampsCountFromTheEarliest) {
  const std::string text =
      "FIELDS x y z timestamp\nSIZE 4 4 4 8\nTYPE F F F F\nWIDTH 2\nHEIGHT 1\nDATA ascii\n"
      "0 0 0 1700000000.25\n1 1 1 1700000000.125\n";
  const PointCloud cloud = parse_pcd(text, "hesai.pcd");
  EXPECT_EQ(cloud.time_base, 1700000000.125);
  EXPECT_FLOAT_EQ(cloud.points[0].t, 0.125f);
  EXPECT_EQ(cloud.points[1].t, 0.0f);
  EXPECT_FALSE(cloud.has_ring);
}

TEST(Pcd, TruncatedBinaryDataNamesTheDataLine) {
  for (const auto encoding : {PcdEncoding::kBinary, PcdEncoding::kBinaryCompressed}) {
    const std::string bytes = format_pcd(sample_cloud(), encoding);
    const InputError error = expect_input_error(
        [&] { parse_pcd(bytes.substr(0, bytes.size() - 30), "cut.pcd"); }, "cut.pcd", 11, "DATA");
    EXPECT_THAT(error.what(), HasSubstr("truncated"));
  }
}

// A header that claims billions of points is refused before memory is allocated for them (it
// used to allocate 24 bytes a point first: gigabytes, or std::bad_alloc with no file named).
TEST(Pcd, HugePointCountsAreRefusedBeforeAllocating) {
  for (const std::string data : {"binary", "binary_compressed", "ascii"}) {
    const std::string text =
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3000000000\nHEIGHT 1\n"
        "DATA " +
        data + "\n0 0 0\n";
    const InputError error =
        expect_input_error([&] { parse_pcd(text, "huge.pcd"); }, "huge.pcd", 6, "DATA");
    EXPECT_THAT(error.what(), HasSubstr("3000000000")) << data;
  }
  const std::string wrapping =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967296\nHEIGHT 4294967296\nDATA binary\n";
  expect_input_error([&] { parse_pcd(wrapping, "wrap.pcd"); }, "wrap.pcd", 4, "WIDTH");
}

// The 300-byte file: a binary_compressed header whose POINTS and block sizes agree on 4 GB
// of points while the file holds 200 bytes. It used to allocate 4.6 GB, then std::bad_alloc naming
// no file; the sizes are now checked against the bytes there are first.
TEST(Pcd, CompressedSizesBeyondTheFileAreRefusedBeforeAllocating) {
  const std::size_t points = 190000000;  // 22 bytes each: 4.18e9 bytes unpacked, below 4 GiB
  std::string text = "FIELDS x y z intensity ring t\nSIZE 4 4 4 4 2 4\nTYPE F F F F U F\nWIDTH " +
                     std::to_string(points) + "\nHEIGHT 1\nDATA binary_compressed\n";
  const std::uint32_t compressed = 200;
  const auto unpacked = static_cast<std::uint32_t>(points * 22);
  text.append(reinterpret_cast<const char*>(&compressed), 4);
  text.append(reinterpret_cast<const char*>(&unpacked), 4);
  text.append(compressed, '\x01');
  const InputError error =
      expect_input_error([&] { parse_pcd(text, "bomb.pcd"); }, "bomb.pcd", 6, "DATA");
  EXPECT_THAT(error.what(), HasSubstr("cannot unpack to 4180000000 bytes"));
}

// LZF's real best case stays within the bound the check above assumes.
TEST(Pcd, CompressedAllZeroCloudStillReads) {
  PointCloud cloud;
  cloud.points.resize(200000);
  const PointCloud read = parse_pcd(format_pcd(cloud, PcdEncoding::kBinaryCompressed), "zeros.pcd");
  EXPECT_EQ(read.points.size(), cloud.points.size());
}

// A COUNT large enough to wrap SIZE x COUNT around used to give a tiny point record and pass.
TEST(Pcd, HugeCountIsRefusedAtTheCountLine) {
  const std::string text =
      "FIELDS x y z pad\nSIZE 4 4 4 8\nTYPE F F F U\nCOUNT 1 1 1 2305843009213693952\n"
      "WIDTH 1\nHEIGHT 1\nDATA binary\n";
  const InputError error =
      expect_input_error([&] { parse_pcd(text, "count.pcd"); }, "count.pcd", 4, "COUNT");
  EXPECT_THAT(error.what(), HasSubstr("'pad'"));
}

// A binary file's first "keyword" used to be printed raw, control bytes and all.
TEST(Pcd, BinaryGarbageIsQuotedPrintably) {
  const std::string garbage = std::string("\x03\x8d\x1a\x31 4 4\n", 9);
  const InputError error =
      expect_input_error([&] { parse_pcd(garbage, "garbage.pcd"); }, "garbage.pcd", 1);
  EXPECT_THAT(error.what(), HasSubstr("unknown header keyword '\\x03\\x8d\\x1a1'"));
}

TEST(Pcd, TruncatedAsciiDataSaysHowManyPointsCame) {
  const std::string text =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 1\nDATA ascii\n"
      "0 0 0\n1 1 1\n";
  const InputError error =
      expect_input_error([&] { parse_pcd(text, "short.pcd"); }, "short.pcd", 8);
  EXPECT_THAT(error.what(), HasSubstr("2 of 3 points"));
}

TEST(Pcd, UnknownTypeNamesTheTypeLine) {
  const std::string text =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nCOUNT 1 1 1\n"
      "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n";
  const InputError error =
      expect_input_error([&] { parse_pcd(text, "q.pcd"); }, "q.pcd", 4, "TYPE");
  EXPECT_THAT(error.what(), HasSubstr("'Q'"));
  EXPECT_THAT(error.what(), HasSubstr("field 'z'"));
}

TEST(Pcd, InconsistentHeadersAreRejectedWhereTheyAre) {
  const std::string fields = "FIELDS x y z\n";
  expect_input_error(
      [&] { parse_pcd(fields + "SIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n", "a.pcd"); }, "a.pcd",
      2, "SIZE");
  expect_input_error(
      [&] { parse_pcd(fields + "SIZE 4 4 3\nTYPE F F F\nWIDTH 1\nDATA ascii\n", "b.pcd"); },
      "b.pcd", 2, "SIZE");
  expect_input_error(
      [&] {
        parse_pcd(fields + "SIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 3\nDATA ascii\n", "c.pcd");
      },
      "c.pcd", 5, "POINTS");
  expect_input_error(
      [&] { parse_pcd(fields + "SIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA zip\n", "d.pcd"); }, "d.pcd",
      5, "DATA");
  expect_input_error(
      [&] { parse_pcd("FIELDS x z\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n0 0\n", "e.pcd"); },
      "e.pcd", 1, "FIELDS");
  expect_input_error(
      [&] {
        parse_pcd(fields + "SIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n0 zero 0\n", "f.pcd");
      },
      "f.pcd", 6, "y");
  expect_input_error([&] { parse_pcd(fields + "SIZE 4 4 4\n", "g.pcd"); }, "g.pcd", 0);
}

}  // namespace
}  // namespace x2car::io
