#include "x2car/camera/window_motion_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace x2car::camera {
namespace {

constexpr double kHeightM = 1.5;

// 30 s of frames at 10 Hz.
std::vector<double> frame_times() {
  std::vector<double> times;
  for (int i = 0; i < 300; ++i) times.push_back(0.1 * i);
  return times;
}

// A frame that carries its index, for the estimator below.
cv::Mat frame_holding(std::size_t index) {
  return cv::Mat(1, 1, CV_64F, cv::Scalar(static_cast<double>(index)));
}

// Reads the frames' indices and says what the road plane's homography would of the car's motion
// between the first and the last: its turn and its travel over the camera's height, from a speed
// and a yaw rate over time, or too little motion under 0.15 heights (as road_plane_motion.hpp).
SequenceEstimator profile_estimator(const std::vector<double>& times,
                                    std::function<double(double)> speed_mps,
                                    std::function<double(double)> yaw_rate) {
  return [times, speed_mps, yaw_rate](const std::vector<cv::Mat>& frames,
                                      const core::CameraIntrinsics&,
                                      const std::optional<SequenceGuide>&) {
    const auto first = static_cast<std::size_t>(frames.front().at<double>(0, 0));
    const auto last = static_cast<std::size_t>(frames.back().at<double>(0, 0));
    const double span_s = times[last] - times[first];
    const double middle = 0.5 * (times[first] + times[last]);
    const double travel_over_height = speed_mps(middle) * span_s / kHeightM;
    if (travel_over_height < 0.15) return rejected_frame(FrameRejection::kTooLittleMotion);
    FrameEstimate estimate;
    estimate.pair_motion = CameraPairMotion{.turn_about_up = yaw_rate(middle) * span_s,
                                            .travel_over_height = travel_over_height};
    return estimate;
  };
}

TemporalFilterOptions filter_at_height() {
  TemporalFilterOptions filter;
  filter.image_motion_camera_height_m = kHeightM;
  return filter;
}

// A start from standstill at 2 m/s^2 to 20 m/s, a straight stretch at 20 m/s and a long curve at
// 1 deg/s, a window each: the start is refused as accelerating (its first pairs moved too little
// to tell and are left out), the curve as turning, the straight stretch kept and known.
TEST(WindowMotionCheck, AStartFromStandstillAndACurveAreRefused) {
  const std::vector<double> times = frame_times();
  const SequenceEstimator estimator = profile_estimator(
      times, [](double t) { return std::min(2.0 * t, 20.0); },
      [](double t) { return t > 20.0 ? rad_from_deg(1.0) : 0.0; });
  std::vector<std::size_t> reads;
  const auto read = [&reads](std::size_t index) {
    reads.push_back(index);
    return frame_holding(index);
  };
  const std::vector<MotionCheckWindow> windows{
      {0, 99, std::nullopt}, {100, 199, std::nullopt}, {200, 299, std::nullopt}};
  const std::vector<WindowMotionCheck> checks = check_window_motion(
      read, times, windows, 2, 1, 0.25, estimator, core::CameraIntrinsics{}, filter_at_height());
  ASSERT_EQ(checks.size(), 3U);
  for (const WindowMotionCheck& check : checks) {
    EXPECT_EQ(check.pairs, 12U);
    ASSERT_TRUE(check.judgement);
  }
  EXPECT_EQ(checks[0].judgement->refused, FrameVerdict::kAccelerating);
  EXPECT_NEAR(checks[0].judgement->acceleration_mps2, 2.0, 1e-6);
  EXPECT_LT(checks[0].motions.size(), 12U);  // standing and creeping: too little motion
  EXPECT_EQ(checks[1].judgement->refused, std::nullopt);
  EXPECT_NEAR(checks[1].judgement->acceleration_mps2, 0.0, 1e-9);
  EXPECT_EQ(checks[2].judgement->refused, FrameVerdict::kTurning);
  EXPECT_NEAR(checks[2].judgement->yaw_rate, rad_from_deg(1.0), 1e-9);
  // The pairs' times are from the window's first frame, and the speeds those of the profile.
  EXPECT_NEAR(checks[1].times.front(), 0.1, 1e-9);
  EXPECT_NEAR(checks[1].motions.front().speed_over_height, 20.0 / kHeightM, 1e-9);
  // Each frame read once, in increasing order (a video decodes forward): 12 pairs of 2 frames.
  EXPECT_TRUE(std::is_sorted(reads.begin(), reads.end()));
  EXPECT_EQ(std::adjacent_find(reads.begin(), reads.end()), reads.end());
  EXPECT_EQ(reads.size(), 3U * 24U);
}

// A window the pairs cannot tell (a car standing; unreadable frames) is not judged, and stays;
// pairs that would cross a gap in the frames (a stop in the recording) are not taken.
TEST(WindowMotionCheck, WhatThePairsCannotTellIsNotJudged) {
  std::vector<double> times = frame_times();
  const SequenceEstimator cruise = profile_estimator(
      times, [](double) { return 20.0; }, [](double) { return 0.0; });
  const SequenceEstimator standing = profile_estimator(
      times, [](double) { return 0.0; }, [](double) { return 0.0; });
  const std::vector<MotionCheckWindow> window{{0, 99, std::nullopt}};
  const TemporalFilterOptions filter = filter_at_height();

  const auto still = check_window_motion(frame_holding, times, window, 2, 1, 0.25, standing,
                                         core::CameraIntrinsics{}, filter);
  EXPECT_EQ(still[0].pairs, 12U);
  EXPECT_TRUE(still[0].motions.empty());
  EXPECT_FALSE(still[0].judgement);

  const auto unreadable = check_window_motion([](std::size_t) { return cv::Mat(); }, times, window,
                                              2, 1, 0.25, cruise, core::CameraIntrinsics{}, filter);
  EXPECT_FALSE(unreadable[0].judgement);

  // Frames 0.3 s apart: no pair fits in 0.25 s, but sequences of 3 frames fit in 0.5 s.
  for (std::size_t i = 0; i < times.size(); ++i) times[i] = 0.3 * static_cast<double>(i);
  const auto gapped = check_window_motion(frame_holding, times, window, 2, 1, 0.25, cruise,
                                          core::CameraIntrinsics{}, filter);
  EXPECT_EQ(gapped[0].pairs, 0U);
  EXPECT_FALSE(gapped[0].judgement);
  const auto spanned = check_window_motion(frame_holding, times, window, 3, 1, 0.5, cruise,
                                           core::CameraIntrinsics{}, filter);
  EXPECT_EQ(spanned[0].pairs, 12U);
  EXPECT_TRUE(spanned[0].judgement);
}

TEST(WindowMotionCheck, RejectsBadOptionsAndWindows) {
  const std::vector<double> times = frame_times();
  const SequenceEstimator cruise = profile_estimator(
      times, [](double) { return 20.0; }, [](double) { return 0.0; });
  const auto check = [&](const std::vector<MotionCheckWindow>& windows, std::size_t frames,
                         const WindowMotionCheckOptions& options) {
    return check_window_motion(frame_holding, times, windows, frames, 1, 0.25, cruise,
                               core::CameraIntrinsics{}, filter_at_height(), options);
  };
  WindowMotionCheckOptions too_many;
  too_many.min_pairs = too_many.pairs_per_window + 1;
  EXPECT_THROW(check({}, 2, too_many), std::invalid_argument);
  EXPECT_THROW(check({}, 1, {}), std::invalid_argument);
  EXPECT_THROW(check({{0, 300, std::nullopt}}, 2, {}), std::invalid_argument);
  EXPECT_THROW(check({{50, 40, std::nullopt}}, 2, {}), std::invalid_argument);
  EXPECT_TRUE(check({}, 2, {}).empty());
}

}  // namespace
}  // namespace x2car::camera
