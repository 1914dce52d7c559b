// Tests of the KITTI raw OXTS folder reader on folders the tests write.
#include "x2car/io/oxts.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
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

constexpr double kYawEnu = 0.5;       // [rad] the car drives north-east, 28.6 deg left of east
constexpr double kSpeed = 10.0;       // [m/s]
constexpr double kLat0 = 49.0;        // [deg] Karlsruhe, where KITTI drove
constexpr double kLon0 = 8.4;         // [deg]
constexpr double kAlt0 = 115.0;       // [m]
constexpr std::size_t kPackets = 50;  // 10 Hz, 5 s, 50 m
constexpr std::int64_t kStartNs = 1317041965964389445;  // 2011-09-26 12:59:25.964389445 UTC
constexpr std::int64_t kPeriodNs = 100000000;

// WGS84 radii of curvature [m], to advance lat/lon independently of GeographicLib.
constexpr double kA = 6378137.0;
constexpr double kE2 = (1.0 / 298.257223563) * (2.0 - 1.0 / 298.257223563);
double meridian_radius(double lat) {
  return kA * (1 - kE2) / std::pow(1 - kE2 * std::sin(lat) * std::sin(lat), 1.5);
}
double normal_radius(double lat) { return kA / std::sqrt(1 - kE2 * std::sin(lat) * std::sin(lat)); }

// One packet: 30 numbers, as the KITTI devkit writes them (space-separated).
std::string packet_line(double lat, double lon, double alt, double yaw) {
  std::vector<double> v(kOxtsFieldCount, 0.0);
  v[0] = lat;
  v[1] = lon;
  v[2] = alt;
  v[3] = 0.01;   // roll: left side up
  v[4] = -0.02;  // pitch: front up
  v[5] = yaw;
  v[6] = kSpeed * std::sin(kYawEnu);  // vn
  v[7] = kSpeed * std::cos(kYawEnu);  // ve
  v[8] = kSpeed;                      // vf
  v[10] = 0.1;                        // vu
  v[23] = 0.02;                       // pos_accuracy
  v[25] = 4;                          // navstat
  v[26] = 10;                         // numsats
  v[27] = 5;                          // posmode
  std::string line;
  for (const double x : v) line += (line.empty() ? "" : " ") + format_number(x);
  return line + "\n";
}

class OxtsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    drive_ = fs::path(::testing::TempDir()) / "x2car_oxts_test" / info->name();
    fs::remove_all(drive_);
    fs::create_directories(data());
    std::string timestamps;
    const double lat0 = rad_from_deg(kLat0);
    for (std::size_t i = 0; i < kPackets; ++i) {
      const double s = kSpeed * 0.1 * static_cast<double>(i);  // distance driven [m]
      const double lat = kLat0 + deg_from_rad(s * std::sin(kYawEnu) / meridian_radius(lat0));
      const double lon =
          kLon0 + deg_from_rad(s * std::cos(kYawEnu) / (normal_radius(lat0) * std::cos(lat0)));
      write_text_file(data() / fmt::format("{:010}.txt", i),
                      packet_line(lat, lon, kAlt0 + 0.01 * s, kYawEnu));
      timestamps += timestamp(i) + "\n";
    }
    write_text_file(oxts() / "timestamps.txt", timestamps);
    write_text_file(oxts() / "dataformat.txt", "lat: latitude of the oxts-unit (deg)\n");
  }
  void TearDown() override { fs::remove_all(drive_); }

  // KITTI writes nanoseconds: "2011-09-26 12:59:25.964389445".
  static std::string timestamp(std::size_t i) {
    const std::int64_t ns = kStartNs + static_cast<std::int64_t>(i) * kPeriodNs;
    return format_utc_time(ns).substr(0, 19) + fmt::format(".{:09}", ns % 1000000000);
  }
  fs::path oxts() const { return drive_ / "oxts"; }
  fs::path data() const { return oxts() / "data"; }
  fs::path packet(std::size_t i) const { return data() / fmt::format("{:010}.txt", i); }

  fs::path drive_;
};

TEST_F(OxtsTest, ConstructedDriveReadsWithItsHeading) {
  const OxtsLog log = read_oxts_folder(drive_);
  ASSERT_EQ(log.records.size(), kPackets);
  EXPECT_DOUBLE_EQ(log.start_unix_time, 1317041965.964389445);
  EXPECT_EQ(log.enu_origin.latitude_deg, kLat0);
  EXPECT_EQ(log.enu_origin.longitude_deg, kLon0);
  EXPECT_EQ(log.enu_origin.altitude_m, kAlt0);
  EXPECT_LT(log.records.front().position_enu.norm(), 1e-9);
  for (std::size_t i = 1; i < kPackets; ++i) {
    const InsRecord& r = log.records[i];
    EXPECT_NEAR(r.time, 0.1 * static_cast<double>(i), 1e-9) << i;
    const Eigen::Vector3d step = r.position_enu - log.records[i - 1].position_enu;
    EXPECT_NEAR(std::atan2(step.y(), step.x()), kYawEnu, 1e-4) << i;  // positions follow the yaw
    EXPECT_NEAR(step.head<2>().norm(), 1.0, 1e-3) << i;
    EXPECT_NEAR(step.z(), 0.01, 1e-3) << i;
  }
  // Yaw and velocity pass through, up to the meridian convergence (dlon sin(lat), ~8e-6 rad here).
  const InsRecord& last = log.records.back();
  const double dlon_rad =
      last.position_enu.x() / (normal_radius(rad_from_deg(kLat0)) * std::cos(rad_from_deg(kLat0)));
  EXPECT_NEAR(log.records.front().attitude.yaw, kYawEnu, 1e-12);
  EXPECT_NEAR(last.attitude.yaw, kYawEnu + dlon_rad * std::sin(rad_from_deg(kLat0)), 1e-8);
  EXPECT_NEAR(last.attitude.roll, 0.01, 1e-5);
  EXPECT_NEAR(last.attitude.pitch, -0.02, 1e-5);
  const Eigen::Vector3d expected_velocity(kSpeed * std::cos(kYawEnu), kSpeed * std::sin(kYawEnu),
                                          0.1);  // ve, vn, vu
  EXPECT_LT((log.records.front().velocity_enu - expected_velocity).norm(), 1e-12);
  EXPECT_NEAR(std::atan2(last.velocity_enu.y(), last.velocity_enu.x()),
              kYawEnu + dlon_rad * std::sin(rad_from_deg(kLat0)), 1e-8);
  EXPECT_NEAR(last.velocity_enu.norm(), expected_velocity.norm(), 1e-9);
  EXPECT_EQ(last.status, 5);  // posmode
}

TEST_F(OxtsTest, AcceptsTheOxtsFolderItself) {
  EXPECT_EQ(oxts_folder_of(drive_), oxts());
  EXPECT_EQ(oxts_folder_of(oxts()), oxts());
  EXPECT_EQ(read_oxts_folder(oxts()).records.size(), kPackets);
}

TEST_F(OxtsTest, MissingTimestampsOrDataAreNamed) {
  fs::remove(oxts() / "timestamps.txt");
  expect_input_error([&] { read_oxts_folder(drive_); }, (oxts() / "timestamps.txt").string(), 0);
  write_text_file(oxts() / "timestamps.txt", timestamp(0) + "\n");
  fs::remove_all(data());
  expect_input_error([&] { read_oxts_folder(drive_); }, data().string(), 0);
  fs::create_directories(data());
  expect_input_error([&] { read_oxts_folder(drive_); }, data().string(), 0);  // no data files
  // A folder of other logs (a simulated drive's ins/) is read as OXTS, and the error names them.
  const fs::path logs = drive_ / "ins";
  fs::create_directories(logs);
  write_text_file(logs / "novatel_enu.csv", "x\n");
  write_text_file(logs / "ins.csv", "x\n");
  const InputError named =
      expect_input_error([&] { read_oxts_folder(logs); }, (logs / "timestamps.txt").string(), 0);
  EXPECT_THAT(named.what(), HasSubstr("holds ins.csv, novatel_enu.csv: give the log file"));
  const fs::path file = drive_ / "not_a_folder.txt";
  write_text_file(file, "x\n");
  expect_input_error([&] { read_oxts_folder(file); }, file.string(), 0);
}

TEST_F(OxtsTest, CountMismatchSaysBothCounts) {
  fs::remove(packet(kPackets - 1));
  const InputError error = expect_input_error([&] { read_oxts_folder(drive_); },
                                              (oxts() / "timestamps.txt").string(), 0);
  EXPECT_THAT(error.what(), HasSubstr("50 timestamps but 49 data files"));
}

TEST_F(OxtsTest, BadPacketsNameFileAndField) {
  write_text_file(packet(3), "49 8.4 115 0 0 0\n");
  const InputError count =
      expect_input_error([&] { read_oxts_folder(drive_); }, packet(3).string(), 1);
  EXPECT_THAT(count.what(), HasSubstr("expected 30 fields"));
  EXPECT_THAT(count.what(), HasSubstr("found 6"));

  const std::string line = packet_line(kLat0, kLon0, kAlt0, kYawEnu);
  std::vector<std::string> fields;
  for (const std::string_view field : split_fields(line)) fields.emplace_back(field);
  fields[1] = "north";
  write_text_file(packet(3), join(fields, " ") + "\n");
  expect_input_error([&] { read_oxts_folder(drive_); }, packet(3).string(), 1, "lon");

  write_text_file(packet(3), packet_line(kLat0, kLon0, kAlt0, std::nan("")));
  expect_input_error([&] { read_oxts_folder(drive_); }, packet(3).string(), 1, "yaw");

  write_text_file(packet(3), packet_line(kLat0, kLon0, kAlt0, kYawEnu) + "1 2 3\n");
  expect_input_error([&] { read_oxts_folder(drive_); }, packet(3).string(), 2);
}

TEST_F(OxtsTest, BadTimestampsAreLocated) {
  std::string text;
  for (std::size_t i = 0; i < kPackets; ++i)
    text += (i == 2 ? "2011-09-26 13:02:61.0" : timestamp(i)) + "\n";
  write_text_file(oxts() / "timestamps.txt", text);
  const fs::path timestamps = oxts() / "timestamps.txt";
  expect_input_error([&] { read_oxts_folder(drive_); }, timestamps.string(), 3, "timestamp");

  text.clear();
  for (std::size_t i = 0; i < kPackets; ++i) text += timestamp(i == 5 ? 4 : i) + "\n";
  write_text_file(timestamps, text);
  const InputError error =
      expect_input_error([&] { read_oxts_folder(drive_); }, timestamps.string(), 6, "timestamp");
  EXPECT_THAT(error.what(), HasSubstr("1 row(s) repeat the previous time and 0 go back"));
}

}  // namespace
}  // namespace x2car::io
