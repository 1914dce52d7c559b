#include "x2car/core/track_alignment_report.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace x2car {
namespace {

// An alignment with two segments, 10-20 s and 30-50 s, and its two estimates.
TrackAlignment two_segment_alignment() {
  TrackAlignment alignment;
  alignment.track.time = {0.0, 1.0, 2.0};
  alignment.track.heading_enu = alignment.track.speed = alignment.track.curvature = {0.0, 0.0, 0.0};
  alignment.sensor_heading = alignment.heading_offset = alignment.velocity_pitch = {0.0, 0.0, 0.0};
  alignment.pieces = 1;
  alignment.reversing_samples = 4;
  alignment.segmentation.rejections.slow = 7;
  alignment.valid_duration_s = 30.0;
  SegmentAverage yaw;
  yaw.value = 0.02;
  yaw.standard_error = 0.001;
  yaw.outliers = 3;
  yaw.segments = {{.start_time = 10.0, .end_time = 20.0, .value = 0.019},
                  {.start_time = 30.0, .end_time = 50.0, .value = 0.021}};
  alignment.yaw = yaw;
  SegmentAverage velocity = yaw;
  velocity.standard_error = 0.002;
  alignment.velocity_yaw_estimate = velocity;
  SegmentAverage pitch = yaw;
  pitch.segments[0].value = -0.01;
  pitch.segments[1].value = -0.011;
  alignment.velocity_pitch_estimate = pitch;
  return alignment;
}

const Series& series_named(const CalibrationResult& result, const std::string& name) {
  for (const Series& series : result.series) {
    if (series.name == name) return series;
  }
  throw std::out_of_range(name);
}

TEST(TrackAlignmentReport, WritesTheSharedKeysAndTheChosenYaw) {
  const TrackAlignment alignment = two_segment_alignment();
  CalibrationResult result;
  write_track_alignment(alignment, choose_yaw(alignment, YawMethod::kAuto, {}), true, result);
  EXPECT_EQ(result.method, "track_heading");  // the smaller standard error
  EXPECT_DOUBLE_EQ(*result.yaw, 0.02);
  EXPECT_EQ(result.rejections.at("reversing"), 4);
  EXPECT_EQ(result.rejections.at("slow"), 7);
  EXPECT_EQ(result.rejections.at("outlier"), 3);
  EXPECT_EQ(result.support.at("segments"), 2);
  EXPECT_EQ(result.support.at("pieces"), 1);
  EXPECT_DOUBLE_EQ(result.diagnostics.at("valid_duration_s"), 30.0);
  EXPECT_TRUE(result.diagnostics.contains("yaw_disagreement_deg"));
}

TEST(TrackAlignmentReport, SegmentSeriesHaveTheSegmentsMidTimes) {
  const TrackAlignment alignment = two_segment_alignment();
  CalibrationResult result;
  write_track_alignment(alignment, std::nullopt, true, result);
  for (const char* name : {"segment_start_time", "segment_yaw", "segment_pitch"}) {
    EXPECT_THAT(series_named(result, name).time, ::testing::ElementsAre(15.0, 40.0)) << name;
  }
  EXPECT_THAT(series_named(result, "segment_start_time").value, ::testing::ElementsAre(10.0, 30.0));
  EXPECT_THAT(series_named(result, "segment_pitch").value, ::testing::ElementsAre(-0.01, -0.011));
  EXPECT_FALSE(result.yaw);  // no choice: no yaw
}

TEST(TrackAlignmentReport, WithoutEstimatesOnlyTheCountsAndNoSeriesUnlessAsked) {
  TrackAlignment alignment;
  alignment.insufficient_reason = "only 3.0 s";
  alignment.in_short_pieces = 12;
  CalibrationResult result;
  write_track_alignment(alignment, std::nullopt, false, result);
  EXPECT_EQ(result.rejections.at("short_piece"), 12);
  EXPECT_FALSE(result.support.contains("segments"));
  EXPECT_FALSE(result.rejections.contains("outlier"));
  EXPECT_TRUE(result.series.empty());
}

}  // namespace
}  // namespace x2car
