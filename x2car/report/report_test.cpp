#include "x2car/report/report.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "x2car/report/report_assets.hpp"

namespace x2car::report {
namespace {

CalibrationResult lidar_result(std::size_t samples) {
  CalibrationResult result;
  result.sensor = "lidar";
  result.status = CalibrationStatus::kOk;
  result.roll = rad_from_deg(1.5);
  result.pitch = rad_from_deg(-2.0);
  result.yaw = rad_from_deg(0.25);
  result.z = 1.8;
  result.roll_std = result.pitch_std = result.yaw_std = rad_from_deg(0.01);
  result.z_std = 0.002;
  // A reason that tries to end the data's <script> element early.
  result.reason = "note </script><script>alert(1)</script>";
  Series roll{"ground_roll", "rad", {}, {}};
  for (std::size_t i = 0; i < samples; ++i) {
    roll.time.push_back(0.1 * static_cast<double>(i));
    roll.value.push_back(rad_from_deg(1.5) + 1e-3 * std::sin(0.01 * static_cast<double>(i)));
  }
  result.series.push_back(roll);
  return result;
}

ReportInput example_input() {
  ReportInput input;
  input.title = "drive <b>&\"";
  input.command = "x2car calibrate all --input drive";
  ReportSensor lidar{"lidar_roof", lidar_result(20000), std::nullopt, std::nullopt, {}};
  io::SensorMounting truth;
  truth.rotation = {rad_from_deg(1.49), rad_from_deg(-2.0), rad_from_deg(0.2)};
  truth.translation = {1.0, 0.0, 1.79};
  lidar.truth = truth;
  eval::SensorEvaluation evaluation;
  evaluation.whole_log = lidar_result(0);
  evaluation.segments.push_back({{0.0, 60.0}, true, lidar_result(0)});
  lidar.evaluation = evaluation;
  input.sensors.push_back(lidar);

  ReportSensor camera{"camera_front",
                      insufficient_data("camera", "only 43 frames"),
                      std::nullopt,
                      std::nullopt,
                      {}};
  camera::FrameView view;
  view.name = "000001.png";
  view.time_s = 12.5;
  view.jpeg = "ab";  // base64 "YWI="
  view.lines.push_back({{1.0, 2.0}, {30.0, 40.0}, camera::LineRole::kRoad});
  view.estimate.road_vanishing_point_px = {600.0, 170.0};
  camera.frames.push_back(view);
  input.sensors.push_back(camera);
  return input;
}

TEST(ReportData, CarriesResultsTruthEvaluationAndFrames) {
  ReportOptions options;
  options.max_points_per_series = 500;
  const io::Json data = report_data_json(example_input(), options);
  EXPECT_EQ(data["title"], "drive <b>&\"");
  ASSERT_EQ(data["sensors"].size(), 2U);
  const io::Json& lidar = data["sensors"][0];
  EXPECT_EQ(lidar["name"], "lidar_roof");
  EXPECT_NEAR(lidar["result"]["roll_deg"].get<double>(), 1.5, 1e-12);
  EXPECT_NEAR(lidar["truth"]["yaw_deg"].get<double>(), 0.2, 1e-12);
  EXPECT_NEAR(lidar["truth"]["z_m"].get<double>(), 1.79, 1e-12);
  const io::Json& series = lidar["result"]["series"][0];
  EXPECT_EQ(series["name"], "ground_roll");
  EXPECT_LE(series["value"].size(), 500U);
  EXPECT_EQ(series["time"].size(), series["value"].size());
  // Values to 6 significant digits: 1.5 deg in rad is 0.0261799...
  EXPECT_NEAR(series["value"][0].get<double>(), rad_from_deg(1.5), 1e-7);
  EXPECT_EQ(lidar["evaluation"]["summary"]["segments"], 1);
  EXPECT_TRUE(data["sensors"][1]["truth"].is_null());
  const io::Json& frame = data["sensors"][1]["frames"][0];
  EXPECT_EQ(frame["jpeg_base64"], "YWI=");
  EXPECT_EQ(frame["lines"][0][4], "road");
  EXPECT_EQ(frame["rejection"], "");
  EXPECT_EQ(frame["vanishing_point"][0], 600.0);
}

// The page: one document whose data element reads back as the data, whatever the strings in it,
// with the chart library and the report's script inlined (no network at view time).
TEST(ReportHtml, IsSelfContainedAndItsDataReadsBack) {
  const ReportInput input = example_input();
  const std::string html = render_report_html(input);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0U);
  EXPECT_NE(html.find("<title>x2car report: drive &lt;b&gt;&amp;&quot;</title>"),
            std::string::npos);
  // Three scripts (data, ECharts, report.js) and nothing in them ends one early.
  std::size_t closings = 0;
  for (std::size_t at = html.find("</script"); at != std::string::npos;
       at = html.find("</script", at + 1)) {
    ++closings;
  }
  EXPECT_EQ(closings, 3U);
  const std::string open = "<script type=\"application/json\" id=\"x2car-data\">";
  const std::size_t start = html.find(open) + open.size();
  const std::size_t end = html.find("</script>", start);
  const io::Json back = io::Json::parse(html.substr(start, end - start));
  EXPECT_EQ(back, report_data_json(input));
  EXPECT_EQ(back["sensors"][0]["result"]["reason"], "note </script><script>alert(1)</script>");
  EXPECT_GT(echarts_js().size(), 500'000U);
  EXPECT_NE(html.find(echarts_js().substr(0, 2000)), std::string::npos);
  EXPECT_NE(html.find("window.x2carReport"), std::string::npos);
  // Nothing fetched when it opens.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
}

// A 30-minute log's report stays under ~10 MB (issue 16): four sensors, each with a dozen series
// of 100 Hz samples, are cut to what a plot shows.
TEST(ReportHtml, ALongLogsReportStaysSmall) {
  ReportInput input;
  input.title = "30 minutes";
  for (const char* name : {"ins", "lidar", "radar", "camera"}) {
    CalibrationResult result = lidar_result(0);
    result.sensor = name;
    for (int k = 0; k < 12; ++k) {
      Series series{fmt::format("series_{}", k), "rad", {}, {}};
      for (int i = 0; i < 30 * 60 * 100; ++i) {
        series.time.push_back(1.7e9 + 0.01 * i);
        series.value.push_back(std::sin(0.001 * i + k) + 1e-4 * ((i * 7919) % 101));
      }
      result.series.push_back(std::move(series));
    }
    input.sensors.push_back({name, result, std::nullopt, std::nullopt, {}});
  }
  const std::string html = render_report_html(input);
  EXPECT_LT(html.size(), 10'000'000U);
  const io::Json data = report_data_json(input);
  EXPECT_LE(data["sensors"][3]["result"]["series"][11]["time"].size(), 3000U);
}

TEST(ReportHtml, OptionsAreChecked) {
  ReportOptions options;
  options.max_points_per_series = 1;
  EXPECT_THROW(render_report_html(example_input(), options), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::report
