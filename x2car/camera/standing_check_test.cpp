#include "x2car/camera/standing_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera {
namespace {

const core::CameraIntrinsics kCamera = core::camera_preset("kitti");
const EulerAngles kMounting{rad_from_deg(0.5), rad_from_deg(3.0), rad_from_deg(1.0)};

// Frames at 10 Hz down a textured road, the car `speed_mps` fast; each window is `frames` long.
struct Drive {
  std::vector<double> times;
  std::vector<cv::Mat> images;
};

Drive drive(double speed_mps, std::size_t frames) {
  Drive drive;
  for (std::size_t i = 0; i < frames; ++i) {
    const double time = 0.1 * static_cast<double>(i);
    drive.times.push_back(time);
    drive.images.push_back(testing::road_picture(kMounting, kCamera, speed_mps * time));
  }
  return drive;
}

std::vector<StandingCheck> check(const Drive& drive,
                                 const std::vector<std::pair<std::size_t, std::size_t>>& windows,
                                 const StandingCheckOptions& options = {}) {
  return check_standing([&](std::size_t i) { return drive.images[i]; }, drive.times, windows,
                        cv::Mat(), options);
}

TEST(StandingCheck, ACarStandingStillStoodAndOneDrivingMoved) {
  const Drive standing = drive(0.0, 12);
  const std::vector<StandingCheck> stood = check(standing, {{0, 11}});
  ASSERT_EQ(stood.size(), 1U);
  EXPECT_EQ(stood[0].pairs, 4U);
  EXPECT_EQ(stood[0].pairs_stood, 4U);
  EXPECT_TRUE(stood[0].stood());

  // At walking pace, 1 m/s: half a second moves the road's near texture by pixels.
  const Drive creeping = drive(1.0, 12);
  const std::vector<StandingCheck> moved = check(creeping, {{0, 11}});
  EXPECT_EQ(moved[0].pairs_moved, 4U);
  EXPECT_FALSE(moved[0].stood());
}

// A car that stands for most of a window and drives off at its end: the window is judged by most
// of its pairs, and each window by its own.
TEST(StandingCheck, EachWindowIsJudgedByMostOfItsPairs) {
  Drive drive_off = drive(0.0, 24);
  for (std::size_t i = 0; i < 24; ++i) {
    const double driven_s = std::max(0.0, drive_off.times[i] - 0.7);
    drive_off.images[i] = testing::road_picture(kMounting, kCamera, 5.0 * driven_s);
  }
  const std::vector<StandingCheck> checks = check(drive_off, {{0, 9}, {12, 23}});
  ASSERT_EQ(checks.size(), 2U);
  // Frames 0-7 stand. The window's pairs (0, 5), (1, 6), (2, 7) stood; (4, 9) moved 1 m.
  EXPECT_EQ(checks[0].pairs_stood, 3U);
  EXPECT_EQ(checks[0].pairs_moved, 1U);
  EXPECT_TRUE(checks[0].stood());
  EXPECT_EQ(checks[1].pairs_moved, 4U);
  EXPECT_FALSE(checks[1].stood());
}

// What stays put in a driving car's view (a dashcam's date and speed burnt into the video, the
// bonnet over the bottom of the image) holds its cells still; the scene's travel moves the rest.
// (Counted over all the image's strongest corners, the overlay's letters took most of them and
// a driving car stood.)
TEST(StandingCheck, WhatStaysPutInADrivingCarsViewDoesNotMakeItStand) {
  Drive driving = drive(10.0, 12);
  const cv::Mat bonnet = testing::bonnet_shape(driving.images.front().size(), 0.2);
  for (cv::Mat& image : driving.images) {
    testing::paint_bonnet(image, bonnet);
    for (const int row : {30, 60, 350}) {
      cv::putText(image, "2026-11-29 10:04:38  87 km/h  N 48.1371 E 11.5754", {20, row},
                  cv::FONT_HERSHEY_SIMPLEX, 0.9, cv::Scalar(255), 2);
    }
  }
  const std::vector<StandingCheck> checks = check(driving, {{0, 11}});
  EXPECT_EQ(checks[0].pairs_moved, 4U);
  EXPECT_FALSE(checks[0].stood());
}

// What moves past a standing car (a cyclist crossing in front) holds a few cells; the rest stay
// put. (Traffic that fills a third of the view keeps the window, as before the check.)
TEST(StandingCheck, TrafficPassingAStandingCarDoesNotMakeItDrive) {
  Drive standing = drive(0.0, 12);
  cv::Mat cyclist(100, 80, CV_8UC1);
  cv::randu(cyclist, 0, 255);
  cv::GaussianBlur(cyclist, cyclist, {5, 5}, 1.5);
  for (std::size_t i = 0; i < standing.images.size(); ++i) {
    const int left = 500 + 15 * static_cast<int>(i);
    cyclist.copyTo(standing.images[i](cv::Rect(left, 120, cyclist.cols, cyclist.rows)));
  }
  const std::vector<StandingCheck> checks = check(standing, {{0, 11}});
  EXPECT_GE(checks[0].pairs_stood, 3U);
  EXPECT_TRUE(checks[0].stood());
}

// A scene with nothing to track (night, fog, a blank wall) tells nothing: the window is not
// refused for it.
TEST(StandingCheck, AFeaturelessSceneTellsNothing) {
  Drive blank;
  for (std::size_t i = 0; i < 12; ++i) {
    blank.times.push_back(0.1 * static_cast<double>(i));
    blank.images.emplace_back(kCamera.height, kCamera.width, CV_8UC1, cv::Scalar(90));
  }
  const std::vector<StandingCheck> checks = check(blank, {{0, 11}});
  EXPECT_EQ(checks[0].pairs, 4U);
  EXPECT_EQ(checks[0].pairs_stood + checks[0].pairs_moved, 0U);
  EXPECT_FALSE(checks[0].stood());
}

// Frames further apart than pair_max_gap_s (1 Hz) make no pairs, and an unreadable frame (empty)
// tells nothing.
TEST(StandingCheck, NoPairsOrUnreadableFramesTellNothing) {
  Drive sparse = drive(0.0, 4);
  for (std::size_t i = 0; i < sparse.times.size(); ++i) sparse.times[i] = 2.0 * i;
  EXPECT_EQ(check(sparse, {{0, 3}})[0].pairs, 0U);
  EXPECT_FALSE(check(sparse, {{0, 3}})[0].stood());

  Drive unreadable = drive(0.0, 12);
  for (cv::Mat& image : unreadable.images) image = cv::Mat();
  const std::vector<StandingCheck> checks = check(unreadable, {{0, 11}});
  EXPECT_EQ(checks[0].pairs, 4U);
  EXPECT_FALSE(checks[0].stood());
}

TEST(StandingCheck, RejectsBadOptions) {
  const Drive standing = drive(0.0, 3);
  StandingCheckOptions options;
  options.min_moving_cell_share = 0.0;
  EXPECT_THROW(check(standing, {{0, 2}}, options), std::invalid_argument);
  options = {};
  options.pair_max_gap_s = 0.1;  // below pair_interval_s
  EXPECT_THROW(check(standing, {{0, 2}}, options), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera
