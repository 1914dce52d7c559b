// Tests of the reference GNSS/INS log novatel_enu.csv and its UTC/GPS times.
#include "x2car/io/novatel_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

constexpr std::int64_t kNs = 1000000000;
constexpr char kHeader[] = "gps_time,sow,x,y,z,vn,ve,vu,roll,pitch,azimuth,status\n";
constexpr char kRow0[] = "2026-06-01 10:00:00.000000,122418,1,2,3,0,0,0,0,0,0,4\n";
constexpr char kRow1[] = "2026-06-01 10:00:00.010000,122418.01,1,2,3,0,0,0,0,0,0,4\n";

std::vector<InsRecord> sample_records() {
  std::vector<InsRecord> records;
  for (int i = 0; i < 300; ++i) {
    const double s = static_cast<double>(i);
    InsRecord r;
    r.time = 0.01 * s;
    r.position_enu = {12.345678 * s - 1e-4, -0.1 / (s + 3), 30.0 + 1e-7 * s};
    r.velocity_enu = {10.0 + 0.001 * s, -2.0 / 3.0, 0.0123 * s};
    r.attitude = {rad_from_deg(0.5) - 1e-4 * s, -0.03 + 2e-5 * s, 3.1 - 0.02 * s};  // yaw wraps
    r.status = i % 7 == 0 ? 5 : 4;
    records.push_back(r);
  }
  return records;
}

InputError expect_novatel_error(const std::string& text, std::size_t line,
                                const std::string& field = {}) {
  return expect_input_error([&] { parse_novatel_enu(text, "ins.csv"); }, "ins.csv", line, field);
}

// ---- dates and GPS time ------------------------------------------------------------------------

TEST(UtcTime, FormatsKnownInstants) {
  EXPECT_EQ(format_utc_time(1780308000 * kNs), "2026-06-01 10:00:00.000000");
  EXPECT_EQ(format_utc_time(0), "1970-01-01 00:00:00.000000");
  EXPECT_EQ(format_utc_time(951868800 * kNs), "2000-03-01 00:00:00.000000");
  EXPECT_EQ(format_utc_time(1709251199 * kNs + 999999000), "2024-02-29 23:59:59.999999");
  EXPECT_EQ(format_utc_time(-2208988800 * kNs + 250000), "1900-01-01 00:00:00.000250");
  EXPECT_EQ(format_utc_time(-1000), "1969-12-31 23:59:59.999999");
  EXPECT_EQ(format_utc_time(1780308000 * kNs + 1500), "2026-06-01 10:00:00.000002");  // rounds
}

TEST(UtcTime, ParsesKnownInstants) {
  EXPECT_EQ(parse_utc_time("2026-06-01 10:00:00.000000"), 1780308000 * kNs);
  EXPECT_EQ(parse_utc_time("2026-06-01T10:00:00"), 1780308000 * kNs);
  EXPECT_EQ(parse_utc_time("2024-02-29 23:59:59.5"), 1709251199 * kNs + kNs / 2);
  EXPECT_EQ(parse_utc_time("1900-01-01 00:00:00.000000001"), -2208988800 * kNs + 1);
  // ISO 8601's UTC designators (they were refused).
  EXPECT_EQ(parse_utc_time("2026-06-01T10:00:00.5Z"), 1780308000 * kNs + kNs / 2);
  EXPECT_EQ(parse_utc_time("2026-06-01T10:00:00+00:00"), 1780308000 * kNs);
  // RFC 3339's lowercase t and z, ISO 8601's basic and hour-only zero offsets (they were refused).
  EXPECT_EQ(parse_utc_time("2026-06-01t10:00:00.5z"), 1780308000 * kNs + kNs / 2);
  EXPECT_EQ(parse_utc_time("2026-06-01 10:00:00+0000"), 1780308000 * kNs);
  EXPECT_EQ(parse_utc_time("2026-06-01T10:00:00.25+00"), 1780308000 * kNs + kNs / 4);
}

TEST(UtcTime, FormatAndParseAgreeOverCenturies) {
  for (std::int64_t ns = -2208988800 * kNs; ns < 7258118400 * kNs; ns += 3217 * 86400 * kNs + 7) {
    const std::int64_t us = ns / 1000 * 1000;
    EXPECT_EQ(parse_utc_time(format_utc_time(us)), us) << format_utc_time(us);
  }
}

TEST(UtcTime, RejectsInvalidDateTimes) {
  for (const char* text :
       {"2026-02-29 10:00:00", "2026-13-01 10:00:00", "2026-06-00 10:00:00", "2026-06-01 24:00:00",
        "2026-06-01 10:60:00", "2026-06-01 10:00:60", "2026/06/01 10:00:00", "2026-06-01 10:00:00.",
        "2026-06-01 10:00:00.1234567890", "2026-06-01 10:00:00+02:00", "2026-06-01 10:00:00.Z",
        "2026-06-01 10:00:00+0100", "2026-06-01 10:00:00-05", "2026-06-01 10:00:00Z+00:00",
        "2026-6-1 10:00:00", "1780308000", ""}) {
    EXPECT_FALSE(parse_utc_time(text).has_value()) << text;
  }
}

TEST(GpsTime, SecondsOfWeekOfKnownInstants) {
  // The GPS epoch is 18 s of GPS time in UTC terms today (no leap-second table).
  EXPECT_DOUBLE_EQ(gps_seconds_of_week(kGpsEpochUnixSeconds * kNs), 18.0);
  // Monday 2026-06-01 10:00:00 UTC: one day, ten hours and 18 leap seconds into the GPS week.
  EXPECT_DOUBLE_EQ(gps_seconds_of_week(1780308000 * kNs), 86400.0 + 36000.0 + 18.0);
  // The week rolls over at Sunday 00:00:00 GPS = Saturday 23:59:42 UTC.
  EXPECT_DOUBLE_EQ(gps_seconds_of_week((1780308000 - 122418) * kNs), 0.0);
  EXPECT_DOUBLE_EQ(gps_seconds_of_week((1780308000 - 122418) * kNs - kNs / 4), 604799.75);
}

// ---- writer and reader -------------------------------------------------------------------------

TEST(NovatelCsv, WriterOutputReadsBackExactly) {
  const std::vector<InsRecord> records = sample_records();
  const NovatelLog log = parse_novatel_enu(format_novatel_enu(records), "ins.csv");
  EXPECT_EQ(log.start_unix_time, kDefaultStartUnixTime);
  ASSERT_EQ(log.records.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const InsRecord& a = log.records[i];
    const InsRecord& e = records[i];
    EXPECT_NEAR(a.time, e.time, 1e-12) << i;  // written to the microsecond
    EXPECT_EQ(a.position_enu, e.position_enu) << i;
    EXPECT_EQ(a.velocity_enu, e.velocity_enu) << i;
    EXPECT_EQ(a.attitude.roll, e.attitude.roll) << i;
    EXPECT_EQ(a.attitude.pitch, e.attitude.pitch) << i;
    EXPECT_NEAR(angle_difference(a.attitude.yaw, e.attitude.yaw), 0.0, 1e-15) << i;
    EXPECT_GT(a.attitude.yaw, -kPi);
    EXPECT_LE(a.attitude.yaw, kPi);
    EXPECT_EQ(a.status, e.status) << i;
  }
}

TEST(NovatelCsv, WritesTheReferenceFields) {
  InsRecord r;
  r.time = 0.25;
  r.position_enu = {1.5, -2.25, 3.0};
  r.velocity_enu = {10.0, 1.0, -0.5};   // east, north, up
  r.attitude = {0.01, -0.02, kPi / 2};  // facing north
  r.status = 4;
  const std::string text = format_novatel_enu({&r, 1}, 1780308000.5);
  const std::vector<TextLine> lines = split_lines(text);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(split_fields(lines[0].text).front(), "gps_time");
  EXPECT_EQ(split_fields(lines[0].text).size(), 12u);
  EXPECT_EQ(lines[1].text,
            "2026-06-01 10:00:00.750000,122418.750000,1.5,-2.25,3,1,10,-0.5,0.01,-0.02,0,4");
}

TEST(NovatelCsv, ReaderConvertsAzimuthAndVelocityOrderToEnu) {
  const std::string text = std::string(kHeader) +
                           "2026-06-01 10:00:00.5,1,0,0,0,1,2,3,0.1,0.2,0,4\n"
                           "2026-06-01 10:00:00.6,1,0,0,0,0,0,0,0,0,1.5707963267948966,4\n"
                           "2026-06-01 10:00:00.7,1,0,0,0,0,0,0,0,0,3.141592653589793,4\n";
  const NovatelLog log = parse_novatel_enu(text, "ins.csv");
  ASSERT_EQ(log.records.size(), 3u);
  EXPECT_EQ(log.start_unix_time, 1780308000.5);
  EXPECT_DOUBLE_EQ(log.records[2].time, 0.2);
  EXPECT_EQ(log.records[0].velocity_enu, Eigen::Vector3d(2, 1, 3));  // file: north, east, up
  EXPECT_EQ(log.records[0].attitude.roll, 0.1);
  EXPECT_EQ(log.records[0].attitude.pitch, 0.2);
  EXPECT_DOUBLE_EQ(log.records[0].attitude.yaw, kPi / 2);   // azimuth 0 = north = ENU +pi/2
  EXPECT_NEAR(log.records[1].attitude.yaw, 0.0, 1e-15);     // azimuth pi/2 = east
  EXPECT_DOUBLE_EQ(log.records[2].attitude.yaw, -kPi / 2);  // azimuth pi = south
}

TEST(NovatelCsv, WriterRejectsNonFiniteStart) {
  EXPECT_THROW(format_novatel_enu(sample_records(), std::nan("")), std::invalid_argument);
}

// ---- bad input ---------------------------------------------------------------------------------

TEST(NovatelCsv, WrongFieldCountNamesTheLine) {
  const InputError error = expect_novatel_error(
      std::string(kHeader) + kRow0 + "2026-06-01 10:00:00.01,1,2,3,0,0,0,0,0,0,4\n", 3);
  EXPECT_THAT(error.what(), HasSubstr("expected 12"));
  EXPECT_THAT(error.what(), HasSubstr("found 11"));
}

TEST(NovatelCsv, NonNumericFieldIsNamed) {
  expect_novatel_error(
      std::string(kHeader) + kRow0 + "2026-06-01 10:00:00.01,1,2,north,3,0,0,0,0,0,0,4\n", 3,
      "y_north");
}

TEST(NovatelCsv, NanIsRejected) {
  expect_novatel_error(std::string(kHeader) + "2026-06-01 10:00:00,1,2,3,4,0,0,0,nan,0,0,4\n", 2,
                       "roll");
  expect_novatel_error(std::string(kHeader) + "2026-06-01 10:00:00,1,2,3,4,0,0,0,0,0,inf,4\n", 2,
                       "azimuth");
}

TEST(NovatelCsv, ImplausibleValuesAreRejectedAtTheirField) {
  const std::string head = kHeader;
  expect_novatel_error(head + "2026-06-01 10:00:00,1,2,1e308,4,0,0,0,0,0,0,4\n", 2, "y_north");
  expect_novatel_error(head + "2026-06-01 10:00:00,1,2,3,4,0,5000,0,0,0,0,4\n", 2, "v_east");
  const InputError degrees =
      expect_novatel_error(head + "2026-06-01 10:00:00,1,2,3,4,0,0,0,0,0,271.5,4\n", 2, "azimuth");
  EXPECT_THAT(degrees.what(), HasSubstr("'271.5' rad is beyond"));
}

TEST(NovatelCsv, UnparsableDateIsRejected) {
  const InputError error = expect_novatel_error(
      std::string(kHeader) + kRow0 + "2026-06-31 10:00:00.02,1,2,3,4,0,0,0,0,0,0,4\n", 3,
      "gps_time");
  EXPECT_THAT(error.what(), HasSubstr("2026-06-31"));
}

TEST(NovatelCsv, NonIntegerStatusIsRejected) {
  expect_novatel_error(std::string(kHeader) + "2026-06-01 10:00:00,1,2,3,4,0,0,0,0,0,0,4.5\n", 2,
                       "status");
  const NovatelLog log = parse_novatel_enu(
      std::string(kHeader) + "2026-06-01 10:00:00,1,2,3,4,0,0,0,0,0,0,4.0\n", "ins.csv");
  EXPECT_EQ(log.records.at(0).status, 4);
}

TEST(NovatelCsv, DuplicateAndBackwardTimestampsAreCountedAndLocated) {
  const std::string text = std::string(kHeader) + kRow0 + kRow1 + kRow1 + kRow0 + kRow1 + kRow1;
  const InputError error = expect_novatel_error(text, 4, "gps_time");
  EXPECT_THAT(error.what(), HasSubstr("2 row(s) repeat the previous time and 1 go back"));
  EXPECT_THAT(error.what(), HasSubstr("the first is line 4"));
}

TEST(NovatelCsv, MissingHeaderOrRowsIsRejected) {
  expect_novatel_error(std::string(kRow0) + kRow1, 1, "1");
  expect_novatel_error(kHeader, 0);
  expect_novatel_error("", 0);
}

TEST(NovatelCsv, FileErrorsNameTheFile) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "x2car_novatel_test_absent.csv";
  expect_input_error([&] { read_novatel_enu(path); }, path.string(), 0);
}

TEST(NovatelCsv, WritesAndReadsAFile) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "x2car_novatel_test.csv";
  write_novatel_enu(path, sample_records(), 1780308000.0);
  EXPECT_EQ(read_novatel_enu(path).records.size(), sample_records().size());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace x2car::io
