#include "x2car/eval/eval_json.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "x2car/core/error.hpp"

namespace x2car::eval {
namespace {

CalibrationResult ok_result(double yaw_deg) {
  CalibrationResult result;
  result.sensor = "radar";
  result.method = "velocity";
  result.status = CalibrationStatus::kOk;
  result.yaw = rad_from_deg(yaw_deg);
  result.yaw_std = rad_from_deg(0.01);
  return result;
}

SensorEvaluation example() {
  SensorEvaluation evaluation;
  evaluation.whole_log = ok_result(90.0);
  evaluation.segments.push_back({{0.0, 60.0}, true, ok_result(90.02)});
  evaluation.segments.push_back({{60.0, 120.0}, false, insufficient_data("radar", "too slow")});
  return evaluation;
}

TEST(EvalJson, RoundTripsAndSummarises) {
  const io::Json json =
      evaluation_to_json(example(), {.include_series = false, .include_timing = false});
  EXPECT_EQ(json["summary"]["segments"], 2);
  EXPECT_EQ(json["summary"]["with_estimate"], 1);
  EXPECT_NEAR(json["summary"]["yaw"]["mean_deg"].get<double>(), 90.02, 1e-9);
  const SensorEvaluation back = evaluation_from_json(json, "eval.json");
  EXPECT_NEAR(deg_from_rad(*back.whole_log.yaw), 90.0, 1e-12);
  ASSERT_EQ(back.segments.size(), 2U);
  EXPECT_EQ(back.segments[0].span.end_s, 60.0);
  EXPECT_TRUE(back.segments[0].straight);
  EXPECT_FALSE(back.segments[1].straight);
  EXPECT_EQ(back.segments[1].result.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(back.segments[1].result.reason, "too slow");
  // Written again, the same bytes.
  EXPECT_EQ(evaluation_to_json(back, {.include_series = false, .include_timing = false}).dump(),
            json.dump());
}

TEST(EvalJson, ErrorsNameTheField) {
  io::Json json = evaluation_to_json(example());
  json["segments"][1]["end_s"] = "soon";
  try {
    evaluation_from_json(json, "eval.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("eval.json"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("segments[1].end_s"), std::string::npos)
        << error.what();
  }
  json = evaluation_to_json(example());
  json.erase("whole_log");
  EXPECT_THROW(evaluation_from_json(json, "eval.json"), InputError);
  EXPECT_THROW(evaluation_from_json(io::Json::array(), "eval.json"), InputError);
}

}  // namespace
}  // namespace x2car::eval
