// Tests of the header-driven generic GNSS/INS CSV reader and its writer.
#include "x2car/io/ins_csv.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/geodetic.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

std::vector<InsRecord> parse(const std::string& text, const InsCsvOptions& options = {}) {
  return parse_ins_csv(text, "ins.csv", options);
}

InputError expect_csv_error(const std::string& text, std::size_t line,
                            const std::string& field = {}) {
  return expect_input_error([&] { parse_ins_csv(text, "ins.csv"); }, "ins.csv", line, field);
}

// ---- columns -----------------------------------------------------------------------------------

TEST(InsCsvColumns, AnyOrderAnyCaseAndUnknownColumnsIgnored) {
  const std::vector<InsRecord> r = parse(
      " Yaw ,TIME,note,Z,x,Y,pitch,Roll,speed\n"
      "0.3,1.5,first row,3,1,2,0.2,0.1,n/a\n"
      "-0.3,1.6,second,6,4,5,0.02,0.01,n/a\n");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].time, 1.5);
  EXPECT_EQ(r[0].position_enu, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r[0].attitude.roll, 0.1);
  EXPECT_EQ(r[0].attitude.pitch, 0.2);
  EXPECT_EQ(r[0].attitude.yaw, 0.3);
  EXPECT_EQ(r[1].position_enu, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(r[1].attitude.yaw, -0.3);
  EXPECT_EQ(r[1].status, 0);
}

TEST(InsCsvColumns, EastNorthUpAndVelocityAliases) {
  for (const char* velocity : {"vx,vy,vz", "ve,vn,vu", "v_east,v_north,v_up"}) {
    const std::vector<InsRecord> r = parse(std::string("time_s,east,north,up,") + velocity +
                                           ",roll,pitch,yaw\n" + "0,1,2,3,4,5,6,0,0,0\n");
    ASSERT_EQ(r.size(), 1u) << velocity;
    EXPECT_EQ(r[0].position_enu, Eigen::Vector3d(1, 2, 3)) << velocity;
    EXPECT_EQ(r[0].velocity_enu, Eigen::Vector3d(4, 5, 6)) << velocity;  // east, north, up
  }
}

TEST(InsCsvColumns, MissingVelocityGivesZeroVelocities) {
  const std::vector<InsRecord> r =
      parse("time,x,y,z,roll,pitch,yaw\n0,1,2,3,0,0,0\n1,2,2,3,0,0,0\n");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[1].velocity_enu, Eigen::Vector3d::Zero());
}

TEST(InsCsvColumns, DegreeSuffixConvertsToRadians) {
  const std::vector<InsRecord> r =
      parse("time,x,y,z,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,1,-2,90\n");
  EXPECT_DOUBLE_EQ(r[0].attitude.roll, rad_from_deg(1.0));
  EXPECT_DOUBLE_EQ(r[0].attitude.pitch, rad_from_deg(-2.0));
  EXPECT_DOUBLE_EQ(r[0].attitude.yaw, kPi / 2);
}

TEST(InsCsvColumns, HeadingAndAzimuthAreClockwiseFromNorth) {
  // Heading 0 faces north = ENU yaw +90 deg; azimuth 90 deg faces east = ENU yaw 0; a car turning
  // right (azimuth growing) turns clockwise, i.e. its ENU yaw shrinks.
  const std::vector<InsRecord> heading =
      parse("time,x,y,z,roll,pitch,heading\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0.1\n");
  EXPECT_THAT(heading[0].attitude.yaw, x2car::testing::AngleNearDeg(kPi / 2, 1e-12));
  EXPECT_THAT(heading[1].attitude.yaw, x2car::testing::AngleNearDeg(kPi / 2 - 0.1, 1e-12));
  const std::vector<InsRecord> azimuth =
      parse("time,x,y,z,roll,pitch,Azimuth_deg\n0,0,0,0,0,0,90\n1,0,0,0,0,0,180\n");
  EXPECT_THAT(azimuth[0].attitude.yaw, x2car::testing::AngleNearDeg(0.0, 1e-12));
  EXPECT_THAT(azimuth[1].attitude.yaw, x2car::testing::AngleNearDeg(-kPi / 2, 1e-12));
}

TEST(InsCsvColumns, YawConventionOptionOverridesTheName) {
  const std::string yaw_text = "time,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n";
  InsCsvOptions options;
  options.yaw_convention = YawConvention::kAzimuth;
  EXPECT_THAT(parse(yaw_text, options)[0].attitude.yaw, x2car::testing::AngleNearDeg(kPi / 2, 0));
  options.yaw_convention = YawConvention::kEnu;
  EXPECT_EQ(parse("time,x,y,z,roll,pitch,heading\n0,0,0,0,0,0,0.25\n", options)[0].attitude.yaw,
            0.25);
}

TEST(InsCsvColumns, AngleUnitOptionAppliesToNamesWithoutSuffix) {
  InsCsvOptions options;
  options.angle_unit = AngleUnit::kDegrees;
  const std::vector<InsRecord> r =
      parse("time,x,y,z,roll,pitch_rad,yaw\n0,0,0,0,1,0.5,-45\n", options);
  EXPECT_DOUBLE_EQ(r[0].attitude.roll, rad_from_deg(1.0));
  EXPECT_EQ(r[0].attitude.pitch, 0.5);  // the suffix wins
  EXPECT_DOUBLE_EQ(r[0].attitude.yaw, rad_from_deg(-45.0));
}

TEST(InsCsvColumns, TimeNsGivesStartUnixTimeAndRelativeTimes) {
  const InsCsvLog log = parse_ins_csv_log(
      "time_ns,x,y,z,roll,pitch,yaw\n"
      "1780308000123456789,0,0,0,0,0,0\n"
      "1780308000133456789,1,0,0,0,0,0\n",
      "ins.csv");
  ASSERT_TRUE(log.start_unix_time.has_value());
  EXPECT_DOUBLE_EQ(*log.start_unix_time, 1780308000.123456789);
  EXPECT_EQ(log.records[0].time, 0.0);
  EXPECT_EQ(log.records[1].time, 0.01);
  EXPECT_FALSE(log.enu_origin.has_value());
  EXPECT_FALSE(parse_ins_csv_log("time,x,y,z,roll,pitch,yaw\n5,0,0,0,0,0,0\n", "g")
                   .start_unix_time.has_value());
}

// Vendors count microseconds or milliseconds since the Unix epoch (issue 17 item 5).
TEST(InsCsvColumns, TimeUsAndTimeMsAreCountsSinceTheEpoch) {
  for (const auto& [column, first, second] :
       {std::tuple{"time_us", "1700000000000000", "1700000000250000"},
        std::tuple{"time_ms", "1700000000000", "1700000000250"}}) {
    const InsCsvLog log =
        parse_ins_csv_log(fmt::format("{},x,y,z,roll,pitch,yaw\n{},0,0,0,0,0,0\n{},1,0,0,0,0,0\n",
                                      column, first, second),
                          "ins.csv");
    ASSERT_EQ(log.records.size(), 2U) << column;
    EXPECT_DOUBLE_EQ(log.records[0].time, 0.0) << column;
    EXPECT_DOUBLE_EQ(log.records[1].time, 0.25) << column;
    ASSERT_TRUE(log.start_unix_time) << column;
    EXPECT_DOUBLE_EQ(*log.start_unix_time, 1700000000.0) << column;
  }
  expect_input_error(
      [] { parse_ins_csv("time_ms,x,y,z,roll,pitch,yaw\n9e300,0,0,0,0,0,0\n", "ins.csv"); },
      "ins.csv", 2, "time_ms");
}

// ROS's orientation: a quaternion of world_from_ins in ENU, instead of roll, pitch and yaw.
TEST(InsCsvColumns, QuaternionAttitude) {
  const EulerAngles truth{0.02, -0.03, 1.2};
  const Eigen::Quaterniond q(rotation_from_euler(truth));
  const std::vector<InsRecord> r = parse(
      fmt::format("time,east,north,up,orientation_x,orientation_y,orientation_z,orientation_w\n"
                  "0,0,0,0,{},{},{},{}\n",
                  q.x(), q.y(), q.z(), q.w()));
  ASSERT_EQ(r.size(), 1U);
  EXPECT_NEAR(r[0].attitude.roll, truth.roll, 1e-12);
  EXPECT_NEAR(r[0].attitude.pitch, truth.pitch, 1e-12);
  EXPECT_NEAR(r[0].attitude.yaw, truth.yaw, 1e-12);
  // Not a unit quaternion; half a quaternion; a quaternion and Euler angles.
  expect_csv_error("time,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,3\n", 2, "qw");
  EXPECT_THAT(expect_csv_error("time,x,y,z,qx,qy,qw\n0,0,0,0,0,0,1\n", 1).what(),
              HasSubstr("'qz' or 'quat_z' or 'orientation_z'"));
  expect_csv_error("time,x,y,z,qx,qy,qz,qw,roll,pitch,yaw\n0,0,0,0,0,0,0,1,0,0,0\n", 1, "qw");
}

// A vendor's names mapped to x2car's (--columns time=...,east=...).
TEST(InsCsvColumns, ColumnNamesMapAVendorsHeader) {
  InsCsvOptions options;
  options.column_names = {{"time", "GPS Time"},   {"east", "E"},     {"north", "N"},    {"up", "U"},
                          {"heading_deg", "Hdg"}, {"roll_deg", "R"}, {"pitch_deg", "P"}};
  const std::vector<InsRecord> r =
      parse("GPS Time,E,N,U,R,P,Hdg\n10.5,1,2,3,0,0,90\n10.6,2,2,3,0,0,90\n", options);
  ASSERT_EQ(r.size(), 2U);
  EXPECT_DOUBLE_EQ(r[1].time, 10.6);
  EXPECT_DOUBLE_EQ(r[1].position_enu.x(), 2.0);
  EXPECT_NEAR(r[0].attitude.yaw, 0.0, 1e-12);  // heading 90 deg = east = ENU yaw 0
  // A mapped column the header lacks, and a key the reader does not know.
  options.column_names["status"] = "Mode";
  expect_input_error(
      [&] { parse_ins_csv("GPS Time,E,N,U,R,P,Hdg\n1,1,2,3,0,0,90\n", "ins.csv", options); },
      "ins.csv", 1, "Mode");
  InsCsvOptions unknown;
  unknown.column_names = {{"speed", "V"}};
  EXPECT_THROW(unknown.Check(), std::invalid_argument);
}

TEST(InsCsvColumns, StatusIsAnInteger) {
  const std::string header = "time,x,y,z,roll,pitch,yaw,status\n";
  const std::vector<InsRecord> r = parse(header + "0,0,0,0,0,0,0,4\n1,0,0,0,0,0,0,5.0\n");
  EXPECT_EQ(r[0].status, 4);
  EXPECT_EQ(r[1].status, 5);
  expect_csv_error(header + "0,0,0,0,0,0,0,4.5\n", 2, "status");
}

// ---- geodetic positions ------------------------------------------------------------------------

TEST(InsCsvGeodetic, LatLonAltBecomeLocalEnuAtTheFirstRow) {
  const InsCsvLog log = parse_ins_csv_log(
      "time,latitude,longitude,altitude,vn,ve,vu,roll,pitch,yaw\n"
      "0,49,8.4,110,0,0,0,0,0,0\n"
      "1,49.001,8.4,112,1,2,3,0,0,0\n",
      "ins.csv");
  ASSERT_TRUE(log.enu_origin.has_value());
  EXPECT_EQ(log.enu_origin->latitude_deg, 49.0);
  EXPECT_EQ(log.enu_origin->altitude_m, 110.0);
  EXPECT_LT(log.records[0].position_enu.norm(), 1e-9);
  const Eigen::Vector3d expected =
      LocalEnuFrame({49, 8.4, 110}).enu_from_geodetic({49.001, 8.4, 112});
  EXPECT_LT((log.records[1].position_enu - expected).norm(), 1e-9);
  EXPECT_NEAR(log.records[1].position_enu.y(), 111.21, 0.01);  // 0.001 deg of latitude at 49 deg
  EXPECT_NEAR(log.records[1].position_enu.z(), 2.0, 0.01);
  // vn, ve, vu are north, east, up; due north the local-level axes barely turn.
  EXPECT_LT((log.records[1].velocity_enu - Eigen::Vector3d(2, 1, 3)).norm(), 1e-4);
}

TEST(InsCsvGeodetic, AttitudeIsTurnedIntoTheOriginsAxes) {
  // 0.1 deg of longitude east at 49 deg: local east points north of the origin's east by the
  // meridian convergence dlon sin(lat) (~0.075 deg), so a yaw of 0 reported there is +0.075 deg
  // here.
  const InsCsvLog log = parse_ins_csv_log(
      "time,lat,lon,alt,roll,pitch,yaw\n0,49,8.4,0,0,0,0\n1,49,8.5,0,0,0,0\n", "ins.csv");
  EXPECT_NEAR(log.records[0].attitude.yaw, 0.0, 1e-12);
  EXPECT_NEAR(log.records[1].attitude.yaw, rad_from_deg(0.1) * std::sin(rad_from_deg(49.0)), 1e-6);
}

TEST(InsCsvGeodetic, RadianSuffixAndLatitudeRange) {
  const std::string lat = format_number(rad_from_deg(49.0));
  const std::vector<InsRecord> r = parse("time,lat_rad,lon_rad,alt,roll,pitch,yaw\n0," + lat + "," +
                                         format_number(rad_from_deg(8.4)) + ",0,0,0,0\n1," + lat +
                                         "," + format_number(rad_from_deg(8.401)) + ",0,0,0,0\n");
  const Eigen::Vector3d expected = LocalEnuFrame({49, 8.4, 0}).enu_from_geodetic({49, 8.401, 0});
  EXPECT_LT((r[1].position_enu - expected).norm(), 1e-6);
  EXPECT_NEAR(r[1].position_enu.x(), 73.0, 0.5);  // 0.001 deg of longitude at 49 deg
  expect_csv_error("time,lat,lon,alt,roll,pitch,yaw\n0,91,0,0,0,0,0\n", 2, "lat");
}

// ---- bad input ---------------------------------------------------------------------------------

TEST(InsCsvErrors, MissingColumnsAreListedWithTheNamesAccepted) {
  InputError error = expect_csv_error("time,x,y,roll,pitch\n0,0,0,0,0\n", 1);
  EXPECT_THAT(error.what(),
              HasSubstr("missing column(s): 'z' or 'up'; 'yaw' or 'heading' or 'azimuth'"));
  error = expect_csv_error("t,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n", 1);
  EXPECT_THAT(error.what(), HasSubstr("'time' or 'time_s' or 'time_ns'"));
  error = expect_csv_error("time,roll,pitch,yaw\n0,0,0,0\n", 1);
  EXPECT_THAT(error.what(), HasSubstr("a position: 'x,y,z' or 'east,north,up'"));
  EXPECT_THAT(error.what(), HasSubstr("'lat,lon,alt'"));
  error = expect_csv_error("time,lat,lon,roll,pitch,yaw\n0,0,0,0,0,0\n", 1);
  EXPECT_THAT(error.what(), HasSubstr("'alt' or 'altitude'"));
}

TEST(InsCsvErrors, IncompleteVelocityIsRejected) {
  const InputError error =
      expect_csv_error("time,x,y,z,vx,vy,roll,pitch,yaw\n0,0,0,0,0,0,0,0,0\n", 1);
  EXPECT_THAT(
      error.what(),
      HasSubstr(
          "'vz' or 'vu' or 'v_up' or 'vel_u' or 'vel_up' (velocity is optional, but needs all "
          "three)"));
}

TEST(InsCsvErrors, TwoColumnsForOneQuantityAreRejected) {
  InputError error =
      expect_csv_error("time,time_s,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0,0\n", 1, "time_s");
  EXPECT_THAT(error.what(), HasSubstr("'time' (1) and 'time_s' (2)"));
  expect_csv_error("time,x,y,z,roll,pitch,yaw,Heading_deg\n0,0,0,0,0,0,0,0\n", 1, "Heading_deg");
  expect_csv_error("time,x,east,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0,0\n", 1, "east");
}

TEST(InsCsvErrors, EnuAndGeodeticTogetherAreRejected) {
  const InputError error =
      expect_csv_error("time,x,y,z,lat,lon,alt,roll,pitch,yaw\n0,0,0,0,0,0,0,0,0,0\n", 1, "lat");
  EXPECT_THAT(error.what(), HasSubstr("both an ENU position ('x') and a geodetic one ('lat')"));
}

TEST(InsCsvErrors, RowsAreCheckedFieldByField) {
  const std::string header = "# exported\ntime,x,y,z,roll,Pitch,yaw\n";
  const InputError count = expect_csv_error(header + "0,0,0,0,0,0,0\n1,0,0,0,0,0\n", 4);
  EXPECT_THAT(count.what(),
              HasSubstr("expected 7 comma-separated fields as in the header (line 2), "
                        "found 6"));
  expect_csv_error(header + "0,0,0,0,0,level,0\n", 3, "Pitch");
  expect_csv_error(header + "0,0,0,0,0,,0\n", 3, "Pitch");
  expect_csv_error(header + "0,0,0,0,nan,0,0\n", 3, "roll");
  expect_csv_error(header + "0,0,inf,0,0,0,0\n", 3, "y");
  expect_csv_error("time_ns,x,y,z,roll,pitch,yaw\n1.5,0,0,0,0,0,0\n", 2, "time_ns");
}

TEST(InsCsvErrors, NoRowsOrEmptyFile) {
  expect_csv_error("time,x,y,z,roll,pitch,yaw\n", 0);
  expect_csv_error("\n# nothing\n", 0);
}

TEST(InsCsvErrors, RepeatedAndBackwardTimesAreCountedAndLocated) {
  const InputError error = expect_csv_error(
      "time,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n1,0,0,0,0,0,0\n0.5,0,0,0,0,0,0\n"
      "2,0,0,0,0,0,0\n2,0,0,0,0,0,0\n",
      4, "time");
  EXPECT_THAT(error.what(), HasSubstr("2 row(s) repeat the previous time and 1 go back"));
  EXPECT_THAT(error.what(), HasSubstr("the first is line 4"));
}

// ---- issue 11: clear handling of what used to be silent or confusing ---------------------------

TEST(InsCsvColumns, VelEVelNVelUAreVelocityAliases) {
  for (const char* velocity : {"vel_e,vel_n,vel_u", "vel_east,vel_north,vel_up"}) {
    const InsCsvLog log = parse_ins_csv_log(
        std::string("time,x,y,z,") + velocity + ",roll,pitch,yaw\n0,1,2,3,4,5,6,0,0,0\n",
        "ins.csv");
    EXPECT_EQ(log.records[0].velocity_enu, Eigen::Vector3d(4, 5, 6)) << velocity;
    EXPECT_TRUE(log.notices.empty()) << velocity;
  }
}

TEST(InsCsvColumns, IgnoredColumnsAreNamedInANotice) {
  const InsCsvLog log = parse_ins_csv_log(
      "# a comment\ntime,x,y,z,speed,roll,pitch,yaw,vel_forward\n0,1,2,3,4,0,0,0,9\n", "ins.csv");
  ASSERT_EQ(log.notices.size(), 1u);
  EXPECT_THAT(log.notices[0], HasSubstr("ins.csv:2"));
  EXPECT_THAT(log.notices[0], HasSubstr("'speed' (5), 'vel_forward' (9)"));
}

TEST(InsCsvColumns, SemicolonSeparatedFilesAreRead) {
  const InsCsvLog log = parse_ins_csv_log(
      "time;x;y;z;roll;pitch;yaw\n0;1;2;3;0.1;0.2;0.3\n1;4;5;6;0;0;0\n", "ins.csv");
  ASSERT_EQ(log.records.size(), 2u);
  EXPECT_EQ(log.records[1].position_enu, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(log.records[0].attitude.yaw, 0.3);
  const InputError error = expect_csv_error("time;x;y;z;roll;pitch;yaw\n0;1;2;3;0;0\n", 2);
  EXPECT_THAT(error.what(), HasSubstr("semicolon-separated"));
  const InputError comma = expect_csv_error("time;x;y;z;roll;pitch;yaw\n0;1,5;2;3;0;0;0\n", 2, "x");
  EXPECT_THAT(comma.what(), HasSubstr("'1,5' (x2car reads decimal points, not commas)"));
}

// Degrees in a column read as radians used to reach the calibrator ("4912 reversing").
TEST(InsCsvErrors, AnglesBeyondTwoPiSuggestTheDegreeSuffix) {
  const std::string header = "time,x,y,z,roll,pitch,yaw\n";
  const InputError error =
      expect_csv_error(header + "0,0,0,0,1,2,0.5\n1,0,0,0,1.5,-2,93.5\n", 3, "yaw");
  EXPECT_THAT(error.what(), HasSubstr("93.5 is beyond +-2 pi"));
  EXPECT_THAT(error.what(), HasSubstr("'yaw_deg'"));
  EXPECT_THAT(error.what(), HasSubstr("--angle-unit deg"));
  expect_csv_error(header + "0,0,0,0,-7,0,0\n", 2, "roll");
  expect_csv_error("time,x,y,z,roll,pitch_deg,yaw\n0,0,0,0,0,400,0\n", 2, "pitch_deg");
  EXPECT_NO_THROW(parse(header + "0,0,0,0,-6.28,6.28,3.2\n"));
}

// 1e308 in a position or velocity used to travel on to the calibrator and come back in a message as
// a 309-digit number.
TEST(InsCsvErrors, ImplausibleValuesAreRejectedAtTheirLine) {
  const InputError position =
      expect_csv_error("time,x,y,z,roll,pitch,yaw\n0,0,1e308,0,0,0,0\n", 2, "y");
  EXPECT_THAT(position.what(), HasSubstr("'1e308' m is beyond +-100000000 m"));
  expect_csv_error("time,x,y,z,vx,vy,vz,roll,pitch,yaw\n0,0,0,0,0,0,-2000,0,0,0\n", 2, "vz");
  expect_csv_error("time,lat,lon,alt,roll,pitch,yaw\n0,49,8,2e5,0,0,0\n", 2, "alt");
  EXPECT_NO_THROW(parse("time,x,y,z,vx,vy,vz,roll,pitch,yaw\n0,5e6,-9e7,4e3,70,-70,3,0,0,0\n"));
}

// Relative times then Unix ones used to fail later as a P-spline "knot intervals" error.
TEST(InsCsvErrors, MixedClocksAreRejectedAtTheLineWhereTheClockChanges) {
  const std::string header = "time,x,y,z,roll,pitch,yaw\n";
  const InputError error = expect_csv_error(
      header + "12.3,0,0,0,0,0,0\n12.4,0,0,0,0,0,0\n1700000000.5,0,0,0,0,0,0\n", 4, "time");
  EXPECT_THAT(error.what(), HasSubstr("mixed clocks"));
  EXPECT_THAT(error.what(), HasSubstr("12.4 s on line 3"));
  expect_csv_error(header + "1700000000.5,0,0,0,0,0,0\n12.3,0,0,0,0,0,0\n", 3, "time");
  const InputError ns = expect_csv_error(
      "time_ns,x,y,z,roll,pitch,yaw\n1700000000000000000,0,0,0,0,0,0\n12300000000,0,0,0,0,0,0\n", 3,
      "time_ns");
  EXPECT_THAT(ns.what(), HasSubstr("mixed clocks"));
}

TEST(InsCsvTimes, ForwardJumpsAreGapsWithTheirLines) {
  std::string text = "time,x,y,z,roll,pitch,yaw\n";
  for (int i = 0; i < 100; ++i) text += fmt::format("{},0,0,0,0,0,0\n", 0.01 * i);
  for (int i = 0; i < 100; ++i) text += fmt::format("{},0,0,0,0,0,0\n", 604800.0 + 0.01 * i);
  const InsCsvLog log = parse_ins_csv_log(text, "ins.csv");
  ASSERT_EQ(log.gaps.size(), 1u);
  EXPECT_EQ(log.gaps[0].record, 100u);
  EXPECT_EQ(log.gaps[0].line_before, 101u);
  EXPECT_EQ(log.gaps[0].line_after, 102u);
  EXPECT_NEAR(log.gaps[0].seconds(), 604800.0 - 0.99, 1e-9);
  EXPECT_THAT(time_gap_notice(log.gaps[0], "ins.csv"), HasSubstr("ins.csv:102"));
}

TEST(InsCsvTimes, GapsNeedBothTheMinimumAndManyMedianSteps) {
  const std::vector<std::size_t> lines{1, 2, 3, 4, 5};
  // 1 Hz with a 4 s dropout: not a gap (below 5 s).
  EXPECT_TRUE(find_time_gaps(std::vector<double>{0, 1, 2, 6, 7}, lines).empty());
  // 1 Hz with a 40 s stop: beyond 5 s but below 50 median steps.
  EXPECT_TRUE(find_time_gaps(std::vector<double>{0, 1, 2, 42, 43}, lines).empty());
  const std::vector<TimeGap> gaps = find_time_gaps(std::vector<double>{0, 1, 2, 62, 63}, lines);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].record, 3u);
  EXPECT_TRUE(find_time_gaps(std::vector<double>{5}, std::vector<std::size_t>{1}).empty());
}

TEST(InsCsvOptions, NamesRoundTripAndUnknownNamesAreRejected) {
  for (const YawConvention c : {YawConvention::kEnu, YawConvention::kAzimuth}) {
    EXPECT_EQ(yaw_convention_from_string(to_string(c)), c);
  }
  for (const AngleUnit u : {AngleUnit::kRadians, AngleUnit::kDegrees}) {
    EXPECT_EQ(angle_unit_from_string(to_string(u)), u);
  }
  EXPECT_THROW(yaw_convention_from_string("ned"), std::invalid_argument);
  EXPECT_THROW(angle_unit_from_string("grad"), std::invalid_argument);
  InsCsvOptions options;
  options.angle_unit = static_cast<AngleUnit>(7);
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

// ---- the writer --------------------------------------------------------------------------------

TEST(InsCsvWriter, OutputReadsBackExactly) {
  std::vector<InsRecord> records(120);
  for (std::size_t i = 0; i < records.size(); ++i) {
    const double s = static_cast<double>(i);
    records[i].time = 0.01 * s;
    records[i].position_enu = {12.345678 * s - 1e-4, -0.1 / (s + 3), 30.0 + 1e-7 * s};
    records[i].velocity_enu = {10.0 + 0.001 * s, -2.0 / 3.0, 0.0123 * s};
    records[i].attitude = {1e-4 * s, -0.03 + 2e-5 * s, 3.1 - 0.06 * s};  // the yaw wraps
  }
  const std::string text = format_ins_csv(records);
  EXPECT_TRUE(text.starts_with("time,x,y,z,vx,vy,vz,roll,pitch,yaw\n"));
  const std::vector<InsRecord> back = parse_ins_csv(text, "ins.csv");
  ASSERT_EQ(back.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(back[i].time, records[i].time);
    EXPECT_EQ(back[i].position_enu, records[i].position_enu);
    EXPECT_EQ(back[i].velocity_enu, records[i].velocity_enu);
    EXPECT_EQ(back[i].attitude.roll, records[i].attitude.roll);
    EXPECT_EQ(back[i].attitude.pitch, records[i].attitude.pitch);
    EXPECT_EQ(back[i].attitude.yaw, records[i].attitude.yaw);  // ENU, written as is
  }
}

TEST(InsCsvErrors, ReaderRejectsBadInput) {
  const std::string header = "time,x,y,z,vx,vy,vz,roll,pitch,yaw\n";
  expect_input_error([&] { parse_ins_csv("t,x,y,z,vx,vy,vz,r,p,y\n0,0,0,0,0,0,0,0,0,0\n", "g"); },
                     "g", 1);
  expect_input_error([&] { parse_ins_csv(header + "0,0,0,0,0,0,0,0,0\n", "g"); }, "g", 2);
  expect_input_error([&] { parse_ins_csv(header + "0,0,0,0,0,0,0,0,x,0\n", "g"); }, "g", 2,
                     "pitch");
  const InputError error = expect_input_error(
      [&] { parse_ins_csv(header + "0,0,0,0,0,0,0,0,0,0\n0,0,0,0,0,0,0,0,0,0\n", "g"); }, "g", 3,
      "time");
  EXPECT_THAT(error.what(), HasSubstr("1 row(s) repeat"));
}

}  // namespace
}  // namespace x2car::io
