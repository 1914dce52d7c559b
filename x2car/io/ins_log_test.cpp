// Tests of reading a GNSS/INS log in any accepted form: detection, the reference layout's exact
// round trip, and format names.
#include "x2car/io/ins_log.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

constexpr char kOxtsPacket[] =
    "49.015 8.43 116.4 0.01 -0.02 0.5 1 2 10 0 0.1 0 0 0 0 0 0 0 0 0 0 0 0 0.02 0.01 4 10 4 4 4\n";

// Records as the simulator writes them: 100 Hz, positions and angles with full double precision.
std::vector<InsRecord> simulated_records() {
  std::vector<InsRecord> records;
  for (int i = 0; i < 500; ++i) {
    const double s = static_cast<double>(i);
    InsRecord r;
    r.time = s / 100.0;  // the nearest double to i/100, as reading the microsecond stamps gives
    r.position_enu = {12.345678 * s - 1e-4, -0.1 / (s + 3), 30.0 + 1e-7 * s};
    r.velocity_enu = {10.0 + 0.001 * s, -2.0 / 3.0, 0.0123 * s};
    r.attitude = {rad_from_deg(0.5) - 1e-4 * s, -0.03 + 2e-5 * s, wrap_angle(3.1 - 0.02 * s)};
    r.status = i % 7 == 0 ? 5 : 4;
    records.push_back(r);
  }
  return records;
}

class InsLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / "x2car_ins_log_test" / info->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    write_text_file(dir_ / name, text);
    return dir_ / name;
  }
  fs::path write_oxts_drive() const {
    const fs::path oxts = dir_ / "drive" / "oxts";
    fs::create_directories(oxts / "data");
    write_text_file(oxts / "data" / "0000000000.txt", kOxtsPacket);
    write_text_file(oxts / "timestamps.txt", "2011-09-26 13:02:25.964389445\n");
    return dir_ / "drive";
  }

  fs::path dir_;
};

TEST_F(InsLogTest, SimulatorReferenceLayoutReadsBackExactly) {
  const std::vector<InsRecord> records = simulated_records();
  const fs::path path = dir_ / "novatel_enu.csv";
  write_novatel_enu(path, records);
  const InsLog log = read_ins_log(path);
  EXPECT_EQ(log.format, InsFormat::kNovatel);
  EXPECT_EQ(log.start_unix_time, kDefaultStartUnixTime);
  EXPECT_FALSE(log.enu_origin.has_value());
  ASSERT_EQ(log.records.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const InsRecord& a = log.records[i];
    const InsRecord& e = records[i];
    EXPECT_EQ(a.time, e.time) << i;
    EXPECT_EQ(a.position_enu, e.position_enu) << i;
    EXPECT_EQ(a.velocity_enu, e.velocity_enu) << i;
    EXPECT_EQ(a.attitude.roll, e.attitude.roll) << i;
    EXPECT_EQ(a.attitude.pitch, e.attitude.pitch) << i;
    // The file holds the azimuth pi/2 - yaw, written shortest-round-trip; converting back costs at
    // most a rounding of the subtraction.
    EXPECT_NEAR(angle_difference(a.attitude.yaw, e.attitude.yaw), 0.0, 1e-15) << i;
    EXPECT_EQ(a.status, e.status) << i;
  }
}

TEST_F(InsLogTest, GenericCsvWriterOutputReadsBackExactly) {
  const std::vector<InsRecord> records = simulated_records();
  const fs::path path = dir_ / "ins.csv";
  write_ins_csv(path, records);
  const InsLog log = read_ins_log(path);
  EXPECT_EQ(log.format, InsFormat::kCsv);
  EXPECT_FALSE(log.start_unix_time.has_value());
  ASSERT_EQ(log.records.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(log.records[i].time, records[i].time) << i;
    EXPECT_EQ(log.records[i].position_enu, records[i].position_enu) << i;
    EXPECT_EQ(log.records[i].velocity_enu, records[i].velocity_enu) << i;
    EXPECT_EQ(log.records[i].attitude.roll, records[i].attitude.roll) << i;
    EXPECT_EQ(log.records[i].attitude.pitch, records[i].attitude.pitch) << i;
    EXPECT_EQ(log.records[i].attitude.yaw, records[i].attitude.yaw) << i;
  }
}

TEST_F(InsLogTest, DetectsEachForm) {
  write_novatel_enu(dir_ / "novatel_enu.csv", simulated_records());
  EXPECT_EQ(detect_ins_format(dir_ / "novatel_enu.csv"), InsFormat::kNovatel);
  // Blank and comment lines before the header do not matter; `gps_time` must be the first field.
  EXPECT_EQ(detect_ins_format(write("a.csv", "\n# exported\n gps_time ,sow\n")),
            InsFormat::kNovatel);
  EXPECT_EQ(detect_ins_format(write("b.csv", "sow,gps_time\n")), InsFormat::kCsv);
  EXPECT_EQ(detect_ins_format(write("c.csv", "time,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n")),
            InsFormat::kCsv);
  EXPECT_EQ(detect_ins_format(write("empty.csv", "")), InsFormat::kCsv);
  const fs::path drive = write_oxts_drive();
  EXPECT_EQ(detect_ins_format(drive), InsFormat::kOxts);
  EXPECT_EQ(detect_ins_format(drive / "oxts"), InsFormat::kOxts);
  expect_input_error([&] { detect_ins_format(dir_ / "absent.csv"); },
                     (dir_ / "absent.csv").string(), 0);
}

TEST_F(InsLogTest, ReadsEachFormWithItsClockAndOrigin) {
  const InsLog csv = read_ins_log(
      write("ins.csv",
            "time_ns,lat,lon,alt,roll,pitch,yaw_deg\n1780308000000000000,49,8.4,110,0,0,90\n"));
  EXPECT_EQ(csv.format, InsFormat::kCsv);
  EXPECT_EQ(csv.start_unix_time, 1780308000.0);
  ASSERT_TRUE(csv.enu_origin.has_value());
  EXPECT_EQ(csv.enu_origin->longitude_deg, 8.4);
  EXPECT_THAT(csv.records.at(0).attitude.yaw, x2car::testing::AngleNearDeg(kPi / 2, 1e-9));

  const InsLog oxts = read_ins_log(write_oxts_drive());
  EXPECT_EQ(oxts.format, InsFormat::kOxts);
  EXPECT_DOUBLE_EQ(oxts.start_unix_time.value(), 1317042145.964389445);
  EXPECT_EQ(oxts.enu_origin.value().latitude_deg, 49.015);
  ASSERT_EQ(oxts.records.size(), 1u);
  EXPECT_NEAR(oxts.records[0].attitude.yaw, 0.5, 1e-12);
  EXPECT_LT((oxts.records[0].velocity_enu - Eigen::Vector3d(2, 1, 0.1)).norm(), 1e-12);
}

TEST_F(InsLogTest, OptionsChooseTheFormAndReachTheCsvReader) {
  const fs::path path = write("ins.csv", "time,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n");
  InsReadOptions options;
  options.csv.yaw_convention = YawConvention::kAzimuth;
  EXPECT_THAT(read_ins_log(path, options).records.at(0).attitude.yaw,
              x2car::testing::AngleNearDeg(kPi / 2, 1e-12));
  options.format = InsFormat::kNovatel;
  expect_input_error([&] { read_ins_log(path, options); }, path.string(), 1, "1");
  options.format = InsFormat::kOxts;
  expect_input_error([&] { read_ins_log(path, options); }, path.string(), 0);
  options.format = InsFormat::kCsv;
  expect_input_error([&] { read_ins_log(write_oxts_drive(), options); }, (dir_ / "drive").string(),
                     0);
}

// A one-week jump is a gap the log reports with its file and line, for the CLI to warn about and a
// calibrator to split at; the reader's cost follows the rows, not the span.
TEST_F(InsLogTest, TimeJumpsBecomeGapsAndNotices) {
  std::string text = "time,x,y,z,vel_e,vel_n,vel_u,roll,pitch,yaw,speed\n";
  for (int i = 0; i < 200; ++i) {
    const double t = 0.01 * i + (i >= 150 ? 604800.0 : 0.0);
    text += fmt::format("{},0,0,0,1,0,0,0,0,0,1\n", t);
  }
  const fs::path path = write("week.csv", text);
  const InsLog log = read_ins_log(path);
  ASSERT_EQ(log.gaps.size(), 1u);
  EXPECT_EQ(log.gaps[0].record, 150u);
  EXPECT_EQ(log.gaps[0].line_after, 152u);
  EXPECT_EQ(log.records[0].velocity_enu, Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(log.notices.size(), 2u);  // the ignored column, then the gap
  EXPECT_THAT(log.notices[0], HasSubstr("'speed' (11)"));
  EXPECT_THAT(log.notices[1], HasSubstr(path.string() + ":152: the time jumps forward by"));
}

TEST_F(InsLogTest, MissingPathIsAnInputError) {
  const fs::path absent = dir_ / "absent";
  const InputError error = expect_input_error([&] { read_ins_log(absent); }, absent.string(), 0);
  EXPECT_THAT(error.what(), HasSubstr("no such file or folder"));
}

TEST(InsFormatNames, RoundTripAndUnknownNamesAreListed) {
  const std::vector<std::string> names = ins_format_names();
  EXPECT_EQ(names, (std::vector<std::string>{"auto", "novatel", "csv", "oxts", "bag"}));
  for (const std::string& name : names) EXPECT_EQ(to_string(ins_format_from_string(name)), name);
  try {
    ins_format_from_string("nmea");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("auto, novatel, csv, oxts, bag"));
  }
}

}  // namespace
}  // namespace x2car::io
