#include "x2car/core/segmentation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace x2car {
namespace {

// A constructed drive sampled at 10 Hz for 60 s:
//   0-5 s standing, 5-20 s straight, 20-24 s a turn, 24-27 s straight (too short),
//   27-29 s slow, 29-45 s straight, a 2 s gap in the log at 40-42 s, 45-60 s straight.
struct ConstructedTrack {
  std::vector<double> times, speeds, curvatures;
};

ConstructedTrack make_track() {
  ConstructedTrack track;
  for (int i = 0; i < 600; ++i) {
    const double t = i / 10.0;  // exact multiples of 0.1 s, so the comparisons below are exact
    if (t >= 40.0 && t < 42.0) continue;  // the gap
    double speed = 10.0, curvature = 0.0;
    if (t < 5.0) speed = 0.0;
    if (t >= 20.0 && t < 24.0) curvature = 0.05;
    if (t >= 27.0 && t < 29.0) speed = 1.0;
    track.times.push_back(t);
    track.speeds.push_back(speed);
    track.curvatures.push_back(curvature);
  }
  return track;
}

TEST(Segmentation, FindsTheStraightMovingRuns) {
  const ConstructedTrack track = make_track();
  const Segmentation segmentation =
      segment_runs(track.times, track.speeds, track.curvatures, {.min_duration_s = 5.0});
  ASSERT_EQ(segmentation.segments.size(), 3u);
  EXPECT_NEAR(segmentation.segments[0].start_time, 5.0, 1e-9);
  EXPECT_NEAR(segmentation.segments[0].end_time, 19.9, 1e-9);
  EXPECT_NEAR(segmentation.segments[1].start_time, 29.0, 1e-9);
  EXPECT_NEAR(segmentation.segments[1].end_time, 39.9, 1e-9);  // the gap splits the run
  EXPECT_NEAR(segmentation.segments[2].start_time, 42.0, 1e-9);
  EXPECT_NEAR(segmentation.segments[2].end_time, 59.9, 1e-9);
  EXPECT_EQ(segmentation.rejections.slow, 50 + 20);
  EXPECT_EQ(segmentation.rejections.curved, 40);
  EXPECT_EQ(segmentation.rejections.short_run, 30);  // 24-27 s
  EXPECT_EQ(segmentation.rejections.trimmed, 0);
  // Every sample is either in a segment or counted once as rejected.
  const auto& r = segmentation.rejections;
  EXPECT_EQ(static_cast<std::int64_t>(segmentation.sample_count()) + r.slow + r.curved +
                r.short_run + r.trimmed,
            static_cast<std::int64_t>(track.times.size()));
}

TEST(Segmentation, TrimsRunEndsAndDropsWhatBecomesTooShort) {
  const ConstructedTrack track = make_track();
  const Segmentation segmentation = segment_runs(track.times, track.speeds, track.curvatures,
                                                 {.min_duration_s = 12.0, .end_trim_s = 1.0});
  // Trimming 1 s off both ends leaves 6-18.9 s (12.9 s, kept), 30-38.9 s (8.9 s, dropped) and
  // 43-58.9 s (15.9 s, kept).
  ASSERT_EQ(segmentation.segments.size(), 2u);
  EXPECT_NEAR(segmentation.segments[0].start_time, 6.0, 1e-9);
  EXPECT_NEAR(segmentation.segments[0].end_time, 18.9, 1e-9);
  EXPECT_NEAR(segmentation.segments[1].start_time, 43.0, 1e-9);
  EXPECT_NEAR(segmentation.segments[1].end_time, 58.9, 1e-9);
}

TEST(Segmentation, NonFiniteSamplesAreRejected) {
  const std::vector<double> times = {0, 1, 2, 3};
  const std::vector<double> speeds = {5, NAN, 5, 5};
  const std::vector<double> curvatures = {0, 0, INFINITY, 0};
  const Segmentation segmentation =
      segment_runs(times, speeds, curvatures, {.min_duration_s = 0.0, .max_gap_s = 2.0});
  EXPECT_EQ(segmentation.rejections.slow, 1);
  EXPECT_EQ(segmentation.rejections.curved, 1);
  EXPECT_EQ(segmentation.segments.size(), 2u);
}

TEST(Segmentation, ExcludedSamplesBreakRunsAndAreCountedFirst) {
  const ConstructedTrack track = make_track();
  // Exclude 10-11 s inside the first straight and 0-1 s, where the car also stands still.
  std::vector<std::uint8_t> excluded(track.times.size(), 0);
  for (std::size_t i = 0; i < track.times.size(); ++i) {
    const double t = track.times[i];
    excluded[i] = (t >= 10.0 && t < 11.0) || t < 1.0;
  }
  const Segmentation segmentation =
      segment_runs(track.times, track.speeds, track.curvatures, {.min_duration_s = 4.0}, excluded);
  ASSERT_EQ(segmentation.segments.size(), 4u);
  EXPECT_NEAR(segmentation.segments[0].end_time, 9.9, 1e-9);
  EXPECT_NEAR(segmentation.segments[1].start_time, 11.0, 1e-9);
  EXPECT_EQ(segmentation.rejections.excluded, 20);
  EXPECT_EQ(segmentation.rejections.slow, 40 + 20);
  const std::vector<std::uint8_t> wrong_size(3, 0);
  EXPECT_THROW(segment_runs(track.times, track.speeds, track.curvatures, {}, wrong_size),
               std::invalid_argument);
}

// The turn at 20-24 s (kappa 0.05 1/m at 10 m/s: 5 m/s^2) stays out under a lateral-acceleration
// gate of 2 m/s^2 with a loose curvature bound; at 5 m/s (1.25 m/s^2) it is kept.
TEST(Segmentation, LateralAccelerationGatesTurnsByHowHardTheyAre) {
  ConstructedTrack track = make_track();
  const SegmentationOptions turns{
      .max_abs_curvature = 0.2, .max_abs_lateral_acceleration = 2.0, .min_duration_s = 5.0};
  Segmentation fast = segment_runs(track.times, track.speeds, track.curvatures, turns);
  EXPECT_EQ(fast.rejections.curved, 40);
  ASSERT_EQ(fast.segments.size(), 3u);
  for (std::size_t i = 0; i < track.times.size(); ++i) {
    if (track.times[i] >= 5.0) track.speeds[i] = std::min(track.speeds[i], 5.0);
  }
  const Segmentation slow = segment_runs(track.times, track.speeds, track.curvatures, turns);
  EXPECT_EQ(slow.rejections.curved, 0);
  ASSERT_EQ(slow.segments.size(), 3u);  // 5-27 s in one run now, then 29-40 s and 42-60 s
  EXPECT_NEAR(slow.segments[0].start_time, 5.0, 1e-9);
  EXPECT_NEAR(slow.segments[0].end_time, 26.9, 1e-9);
  SegmentationOptions bad = turns;
  bad.max_abs_lateral_acceleration = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

TEST(Segmentation, RejectsBadArguments) {
  const std::vector<double> times = {0, 1};
  const std::vector<double> short_list = {1};
  EXPECT_THROW(segment_runs(times, short_list, times), std::invalid_argument);
  EXPECT_THROW(segment_runs(times, times, times, {.max_abs_curvature = 0.0}),
               std::invalid_argument);
}

}  // namespace
}  // namespace x2car
