#include "x2car/camera/corner_tracks.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

namespace x2car::camera {
namespace {

using ::testing::ElementsAre;
using Pair = std::pair<std::size_t, std::size_t>;

TEST(FramePairsIn, PairsEachFrameWithTheFirstFarEnoughOnWithinTheWindow) {
  // 10 Hz with a frame dropped after 0.3 s.
  const std::vector<double> times{0.0, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7};
  // 0.2 s on, at most 0.5: 0.3 pairs with 0.5 (0.2 s on), the last frames with none.
  EXPECT_THAT(frame_pairs_in(times, 0, 6, 0.2, 0.5),
              ElementsAre(Pair{0, 2}, Pair{1, 3}, Pair{2, 4}, Pair{3, 4}, Pair{4, 6}));
  // Only within first..last (inclusive).
  EXPECT_THAT(frame_pairs_in(times, 1, 3, 0.2, 0.5), ElementsAre(Pair{1, 3}));
  // A gap longer than max_gap_s pairs nothing across it; exactly max_gap_s does.
  EXPECT_THAT(frame_pairs_in(times, 3, 4, 0.1, 0.19), ::testing::IsEmpty());
  EXPECT_THAT(frame_pairs_in(times, 3, 4, 0.1, 0.2), ElementsAre(Pair{3, 4}));
  // Times read to a microsecond: 0.2 s at 10 Hz is two frames on, not three.
  const std::vector<double> rounded{0.0, 0.1, 0.19999999};
  EXPECT_THAT(frame_pairs_in(rounded, 0, 2, 0.2, 0.5), ElementsAre(Pair{0, 2}));
}

TEST(StepsWithinGap, EveryStepOfTheSequenceSpansAtMostTheGap) {
  // 10 Hz with a frame dropped after 0.3 s.
  const std::vector<double> times{0.0, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7};
  EXPECT_TRUE(steps_within_gap(times, 0, 3, 1, 0.15));
  EXPECT_FALSE(steps_within_gap(times, 2, 5, 1, 0.15));  // 0.3 -> 0.5
  EXPECT_TRUE(steps_within_gap(times, 2, 5, 1, 0.2));    // exactly the gap
  // Two frames a step: 0.1 -> 0.3 and 0.3 -> 0.6.
  EXPECT_TRUE(steps_within_gap(times, 1, 5, 2, 0.3));
  EXPECT_FALSE(steps_within_gap(times, 1, 5, 2, 0.25));
  // A sequence of one frame has no step.
  EXPECT_TRUE(steps_within_gap(times, 4, 4, 1, 0.0));
}

TEST(EvenlySpaced, SpreadsFromTheFirstToTheLast) {
  EXPECT_THAT(evenly_spaced(10, 4), ElementsAre(0U, 3U, 6U, 9U));
  EXPECT_THAT(evenly_spaced(3, 4), ElementsAre(0U, 1U, 2U));
  EXPECT_THAT(evenly_spaced(5, 1), ElementsAre(0U));
  EXPECT_TRUE(evenly_spaced(0, 4).empty());
}

// Points keep their index through the tracks: those lost (here, on a plain area where nothing
// can be followed) leave gaps, not a shifted order.
TEST(TrackPoints, KeepsEachTracksPointIndex) {
  cv::Mat earlier(120, 160, CV_8UC1, cv::Scalar(128));
  cv::Mat texture = earlier(cv::Rect(80, 0, 80, 120));
  cv::randu(texture, 0, 255);
  cv::GaussianBlur(texture, texture, {5, 5}, 1.0);
  const cv::Mat later = earlier.clone();
  const std::vector<cv::Point2f> points{{20, 60}, {100, 40}, {30, 30}, {120, 80}};
  const std::vector<CornerTrack> tracks = track_points(earlier, later, points);
  ASSERT_EQ(tracks.size(), 2U);
  EXPECT_EQ(tracks[0].point, 1U);
  EXPECT_EQ(tracks[1].point, 3U);
  EXPECT_NEAR(tracks[1].to.x, 120.0F, 0.05F);
}

}  // namespace
}  // namespace x2car::camera
