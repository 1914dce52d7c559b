#include "x2car/eval/segments.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>

namespace x2car::eval {
namespace {

TEST(Segments, MinutesFromTheStartAndALastPieceIfLongEnough) {
  const std::vector<TimeSpan> five = cut_into_segments(10.0, 310.0);
  ASSERT_EQ(five.size(), 5U);
  EXPECT_DOUBLE_EQ(five[0].start_s, 10.0);
  EXPECT_DOUBLE_EQ(five[4].end_s, 310.0);
  EXPECT_EQ(cut_into_segments(0.0, 150.0).size(), 3U);  // 60, 60, 30
  EXPECT_EQ(cut_into_segments(0.0, 140.0).size(), 2U);  // the last 20 s dropped
  EXPECT_TRUE(cut_into_segments(0.0, 20.0).empty());
  SegmentOptions bad;
  bad.segment_s = 0.0;
  EXPECT_THROW(cut_into_segments(0.0, 100.0, bad), std::invalid_argument);
}

std::vector<io::InsRecord> turning_log(double yaw_rate_rad_s) {
  std::vector<io::InsRecord> records;
  for (int i = 0; i < 600; ++i) {
    io::InsRecord record;
    record.time = 0.1 * i;
    record.attitude.yaw = wrap_angle(3.1 + yaw_rate_rad_s * record.time);  // crosses +-pi
    records.push_back(record);
  }
  return records;
}

TEST(Segments, StraightWhenTheHeadingStaysWithinItsRange) {
  EXPECT_TRUE(is_straight(turning_log(rad_from_deg(0.1)), {0.0, 60.0}));   // 6 deg
  EXPECT_FALSE(is_straight(turning_log(rad_from_deg(0.5)), {0.0, 60.0}));  // 30 deg
  EXPECT_FALSE(is_straight(turning_log(0.0), {100.0, 160.0}));             // no record
}

CalibrationResult yaw_result(double yaw, bool ok = true) {
  CalibrationResult result;
  result.status = ok ? CalibrationStatus::kOk : CalibrationStatus::kInsufficientData;
  if (ok) result.yaw = yaw;
  result.seconds = 0.5;
  return result;
}

// The spread over segments, all and straight, of a radar facing backwards: yaws either side of
// +-pi are one direction, not two.
TEST(Segments, SummaryOverTheSegmentsThatGaveAnEstimate) {
  const std::vector<TimeSpan> spans = cut_into_segments(0.0, 240.0);
  const std::vector<double> yaws = {kPi - 0.001, -kPi + 0.001, kPi - 0.002, 0.0};
  std::atomic<int> calls = 0;
  std::size_t last_done = 0;
  const std::vector<SegmentResult> segments = calibrate_segments(
      spans,
      [&](const TimeSpan& span) {
        ++calls;
        const auto index = static_cast<std::size_t>(span.start_s / 60.0);
        return yaw_result(yaws[index], index != 3);
      },
      turning_log(0.0), true, {},
      [&](std::size_t done, std::size_t total) {
        EXPECT_EQ(total, 4U);
        last_done = std::max(last_done, done);
      });
  EXPECT_EQ(calls.load(), 4);
  EXPECT_EQ(last_done, 4U);
  ASSERT_EQ(segments.size(), 4U);
  EXPECT_TRUE(segments[0].straight);  // the log covers the first minute only, without turning
  EXPECT_FALSE(segments[1].straight);
  const SegmentSummary summary = summarise_segments(segments);
  EXPECT_EQ(summary.segments, 4);
  EXPECT_EQ(summary.with_estimate, 3);
  EXPECT_DOUBLE_EQ(summary.mean_seconds, 0.5);
  EXPECT_EQ(summary.yaw.count, 3);
  ASSERT_TRUE(summary.yaw.mean.has_value());
  EXPECT_NEAR(*summary.yaw.mean, kPi - 0.002 / 3.0, 1e-9);
  ASSERT_TRUE(summary.yaw.std_all.has_value());
  EXPECT_LT(*summary.yaw.std_all, 0.002);
  EXPECT_FALSE(summary.roll.mean.has_value());
  EXPECT_EQ(summary.yaw.straight_count, 1);
  EXPECT_FALSE(summary.yaw.std_straight.has_value());  // one straight segment has no spread
}

}  // namespace
}  // namespace x2car::eval
