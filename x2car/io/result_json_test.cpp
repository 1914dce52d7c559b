#include "x2car/io/result_json.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;

constexpr double kJsonExact = 1e-12;

CalibrationResult lidar_result() {
  CalibrationResult result;
  result.sensor = "lidar";
  result.method = "ground_plane+track_heading";
  result.status = CalibrationStatus::kOk;
  result.reason = "7 segments agree";
  result.roll = rad_from_deg(-0.7);
  result.pitch = rad_from_deg(1.3);
  result.yaw = rad_from_deg(2.0);
  result.z = 1.83;
  result.roll_std = rad_from_deg(0.02);
  result.pitch_std = rad_from_deg(0.03);
  result.yaw_std = rad_from_deg(0.1);
  result.z_std = 0.004;
  result.support = {{"frames", 1200}, {"segments", 7}};
  result.rejections = {{"turning", 310}, {"outlier", 2}};
  result.diagnostics = {{"velocity_method_yaw_deg", 2.0125}, {"track_residual_std_m", 0.021}};
  result.series = {{"yaw_per_segment", "rad", {0.0, 10.5}, {0.0349, 0.0350}},
                   {"ground_height", "m", {}, {1.82, std::numeric_limits<double>::quiet_NaN()}}};
  result.seconds = 3.25;
  return result;
}

CalibrationResult ins_result() {
  CalibrationResult result;
  result.sensor = "ins";
  result.status = CalibrationStatus::kOk;
  result.yaw = rad_from_deg(2.0);
  result.yaw_std = rad_from_deg(0.05);
  result.x = 0.5;
  result.y = -0.25;
  return result;
}

void expect_near(const std::optional<double>& actual, const std::optional<double>& expected,
                 const char* name) {
  ASSERT_EQ(actual.has_value(), expected.has_value()) << name;
  if (expected) {
    EXPECT_NEAR(*actual, *expected, kJsonExact) << name;
  }
}

void expect_same_result(const CalibrationResult& actual, const CalibrationResult& expected) {
  EXPECT_EQ(actual.sensor, expected.sensor);
  EXPECT_EQ(actual.method, expected.method);
  EXPECT_EQ(actual.status, expected.status);
  EXPECT_EQ(actual.reason, expected.reason);
  expect_near(actual.roll, expected.roll, "roll");
  expect_near(actual.pitch, expected.pitch, "pitch");
  expect_near(actual.yaw, expected.yaw, "yaw");
  expect_near(actual.x, expected.x, "x");
  expect_near(actual.y, expected.y, "y");
  expect_near(actual.z, expected.z, "z");
  expect_near(actual.roll_std, expected.roll_std, "roll_std");
  expect_near(actual.pitch_std, expected.pitch_std, "pitch_std");
  expect_near(actual.yaw_std, expected.yaw_std, "yaw_std");
  expect_near(actual.z_std, expected.z_std, "z_std");
  EXPECT_EQ(actual.support, expected.support);
  EXPECT_EQ(actual.rejections, expected.rejections);
  EXPECT_EQ(actual.diagnostics, expected.diagnostics);
  EXPECT_EQ(actual.seconds, expected.seconds);
  ASSERT_EQ(actual.series.size(), expected.series.size());
  for (std::size_t i = 0; i < actual.series.size(); ++i) {
    EXPECT_EQ(actual.series[i].name, expected.series[i].name);
    EXPECT_EQ(actual.series[i].unit, expected.series[i].unit);
    EXPECT_EQ(actual.series[i].time, expected.series[i].time);
    ASSERT_EQ(actual.series[i].value.size(), expected.series[i].value.size());
    for (std::size_t k = 0; k < actual.series[i].value.size(); ++k) {
      const double a = actual.series[i].value[k], e = expected.series[i].value[k];
      EXPECT_TRUE(a == e || (std::isnan(a) && std::isnan(e))) << a << " vs " << e;
    }
  }
}

// The InputError parsing `text` as result.json must throw, checked to name that file.
InputError input_error_of(const std::string& text) {
  SCOPED_TRACE("parsing " + text);
  const InputError error =
      x2car::testing::input_error_of([&] { parse_result_json(text, "result.json"); });
  EXPECT_EQ(error.file(), "result.json");
  return error;
}

TEST(ResultJson, WriterOutputReadsBack) {
  expect_same_result(parse_result_json(format_result_json(lidar_result()), "r"), lidar_result());
  expect_same_result(parse_result_json(format_result_json(ins_result()), "r"), ins_result());
}

// A bag's tf prior (issue 17) is written in degrees and metres and reads back.
TEST(ResultJson, PriorReadsBack) {
  CalibrationResult result = lidar_result();
  result.prior = MountingPrior{"base_link",
                               "velodyne",
                               "run.bag /tf_static",
                               {rad_from_deg(0.5), rad_from_deg(-2.0), rad_from_deg(90.0)},
                               Eigen::Vector3d(1.2, 0.0, 1.8)};
  const Json json = result_to_json(result);
  EXPECT_EQ(json.at("prior").at("child"), "velodyne");
  EXPECT_NEAR(json.at("prior").at("yaw_deg").get<double>(), 90.0, kJsonExact);
  EXPECT_NEAR(json.at("prior").at("z_m").get<double>(), 1.8, kJsonExact);
  const CalibrationResult back = parse_result_json(format_result_json(result), "r");
  ASSERT_TRUE(back.prior.has_value());
  EXPECT_EQ(back.prior->parent, "base_link");
  EXPECT_EQ(back.prior->source, "run.bag /tf_static");
  EXPECT_NEAR(back.prior->angles.pitch, rad_from_deg(-2.0), 1e-15);
  EXPECT_NEAR(back.prior->translation.x(), 1.2, 1e-15);
  EXPECT_FALSE(parse_result_json(format_result_json(lidar_result()), "r").prior.has_value());
}

TEST(ResultJson, ShapeFollowsTheDesign) {
  const Json json = result_to_json(lidar_result());
  EXPECT_EQ(json.at("sensor"), "lidar");
  EXPECT_EQ(json.at("status"), "ok");
  EXPECT_NEAR(json.at("yaw_deg").get<double>(), 2.0, kJsonExact);  // degrees, with sign kept
  EXPECT_NEAR(json.at("pitch_deg").get<double>(), 1.3, kJsonExact);
  EXPECT_NEAR(json.at("z_m").get<double>(), 1.83, kJsonExact);
  EXPECT_NEAR(json.at("std_deg").at("yaw").get<double>(), 0.1, kJsonExact);
  EXPECT_FALSE(json.at("std_deg").contains("z_m"));  // a length is not in degrees
  EXPECT_NEAR(json.at("std_m").at("z").get<double>(), 0.004, kJsonExact);
  EXPECT_EQ(json.at("support").at("segments"), 7);
  EXPECT_EQ(json.at("rejections").at("turning"), 310);
  EXPECT_FALSE(json.contains("x_m"));  // only when known
  EXPECT_TRUE(json.at("series").at(1).at("value").at(1).is_null());
  EXPECT_EQ(json.begin().key(), "sensor");  // keys in the documented order
}

TEST(ResultJson, UnobservedAnglesAreNullNeverZero) {
  const std::string text = format_result_json(ins_result());
  EXPECT_THAT(text, HasSubstr("\"roll_deg\": null"));
  EXPECT_THAT(text, HasSubstr("\"pitch_deg\": null"));
  EXPECT_THAT(text, HasSubstr("\"z_m\": null"));
  const Json json = Json::parse(text);
  EXPECT_TRUE(json.at("std_deg").at("roll").is_null());
  EXPECT_TRUE(json.at("std_m").at("z").is_null());
  EXPECT_NEAR(json.at("x_m").get<double>(), 0.5, kJsonExact);
  const CalibrationResult read = parse_result_json(text, "r");
  EXPECT_FALSE(read.roll.has_value());
  EXPECT_FALSE(read.pitch.has_value());
  EXPECT_FALSE(read.z.has_value());
  EXPECT_FALSE(read.roll_std.has_value());
}

TEST(ResultJson, OlderStdDegZmStillReads) {
  const CalibrationResult read = parse_result_json(
      R"({"sensor": "lidar", "status": "ok", "std_deg": {"z_m": 0.004}})", "old.json");
  ASSERT_TRUE(read.z_std.has_value());
  EXPECT_NEAR(*read.z_std, 0.004, kJsonExact);
}

TEST(ResultJson, TimingCanBeLeftOutForIdenticalBytes) {
  CalibrationResult slow = lidar_result();
  CalibrationResult fast = lidar_result();
  slow.seconds = 12.5;
  fast.seconds = 0.5;
  EXPECT_TRUE(result_to_json(slow).contains("seconds"));  // DESIGN §6 keeps it by default
  ResultJsonOptions reproducible;
  reproducible.include_timing = false;
  EXPECT_FALSE(result_to_json(slow, reproducible).contains("seconds"));
  EXPECT_EQ(format_result_json(slow, reproducible), format_result_json(fast, reproducible));
}

TEST(ResultJson, InsufficientDataKeepsItsReason) {
  const CalibrationResult result = insufficient_data("radar", "only 4 s of straight driving");
  const Json json = result_to_json(result);
  EXPECT_EQ(json.at("status"), "insufficient_data");
  EXPECT_TRUE(json.at("yaw_deg").is_null());
  expect_same_result(result_from_json(json, "r"), result);
}

TEST(ResultJson, SeriesCanBeOmitted) {
  ResultJsonOptions options;
  options.include_series = false;
  const Json json = result_to_json(lidar_result(), options);
  EXPECT_FALSE(json.contains("series"));
  EXPECT_TRUE(result_from_json(json, "r").series.empty());
}

TEST(ResultJson, NonFiniteEstimateIsABugNotANull) {
  CalibrationResult result = ins_result();
  result.yaw = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(result_to_json(result), std::logic_error);
  CalibrationResult bad_diagnostic = ins_result();
  bad_diagnostic.diagnostics["lever_m"] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(result_to_json(bad_diagnostic), std::logic_error);
}

TEST(ResultJson, WrongTypesAreRejectedNamingTheField) {
  const std::string head = R"({"sensor": "ins", "status": "ok", )";
  EXPECT_EQ(input_error_of(head + R"("yaw_deg": "2"})").field(), "yaw_deg");
  EXPECT_EQ(input_error_of(head + R"("std_deg": {"roll": true}})").field(), "std_deg.roll");
  EXPECT_EQ(input_error_of(head + R"("support": {"samples": 1.5}})").field(), "support.samples");
  EXPECT_EQ(input_error_of(head + R"("diagnostics": {"lever_m": "1"}})").field(),
            "diagnostics.lever_m");
  EXPECT_EQ(input_error_of(head + R"("series": [{"name": "a", "value": ["x"]}]})").field(),
            "series[0].value[0]");
  EXPECT_EQ(
      input_error_of(head + R"("series": [{"name": "a", "time": [0, 1], "value": [1]}]})").field(),
      "series[0].value");
  EXPECT_EQ(input_error_of(R"({"sensor": "ins", "status": "fine"})").field(), "status");
  EXPECT_EQ(input_error_of(R"({"status": "ok"})").field(), "sensor");
  EXPECT_EQ(input_error_of(R"({"sensor": 3, "status": "ok"})").field(), "sensor");
  EXPECT_THAT(input_error_of(head + R"("yaw_deg": "2"})").what(), HasSubstr("found string"));
  EXPECT_THAT(input_error_of("{\"sensor\": ").what(), HasSubstr("invalid JSON"));
}

TEST(ResultJson, FileRoundTrip) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "x2car_result_json_test.json";
  write_result_json(path, lidar_result());
  expect_same_result(read_result_json(path), lidar_result());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace x2car::io
