#include "x2car/camera/car_region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"

namespace x2car::camera {
namespace {

const core::CameraIntrinsics& camera() {
  static const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  return intrinsics;
}

// Frames of a road driven along (the road's texture moves, the driver weaves: the camera's yaw
// to the road swings by 0.3 deg), with sensor noise on every frame; the bonnet, when given, lit
// 20 % brighter and darker as the car turns.
std::vector<cv::Mat> road_frames(int count, const cv::Mat& bonnet) {
  std::vector<cv::Mat> frames;
  cv::RNG sensor(3);
  for (int i = 0; i < count; ++i) {
    const EulerAngles mounting{0.0, rad_from_deg(1.0), rad_from_deg(0.3 * std::sin(1.3 * i))};
    cv::Mat image = testing::road_picture(mounting, camera(), 7.0 * i);
    if (!bonnet.empty()) testing::paint_bonnet(image, bonnet, 1.0 + 0.2 * std::sin(0.9 * i));
    cv::Mat grain(image.size(), CV_16S);
    sensor.fill(grain, cv::RNG::NORMAL, 0.0, 1.5);
    cv::Mat noisy;
    image.convertTo(noisy, CV_16S);
    noisy += grain;
    noisy.convertTo(image, CV_8U);
    frames.push_back(image);
  }
  return frames;
}

// Where goodFeaturesToTrack finds corners in `image` inside `where` (the motion estimator's
// choice: qualities down to 0.0003).
std::vector<cv::Point2f> corners_in(const cv::Mat& image, const cv::Mat& where) {
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, 2000, 0.0003, 6.0, where);
  return corners;
}

TEST(CarRegion, FindsABonnetThatStaysWhileTheRoadMovesAndTheLightChanges) {
  const cv::Size size(camera().width, camera().height);
  const cv::Mat bonnet = testing::bonnet_shape(size, 0.15);
  const std::vector<cv::Mat> frames = road_frames(8, bonnet);
  const cv::Mat region = car_region_from_frames(frames);
  ASSERT_FALSE(region.empty());
  // Every corner on the bonnet or within 5 px of it is in the region.
  cv::Mat near_bonnet;
  cv::dilate(bonnet, near_bonnet, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(11, 11)));
  const std::vector<cv::Point2f> corners = corners_in(frames[3], near_bonnet);
  ASSERT_GT(corners.size(), 20U);
  for (const cv::Point2f& corner : corners) {
    EXPECT_NE(region.at<unsigned char>(cv::Point(corner)), 0) << corner;
  }
  // And nothing beyond the bonnet grown by the margin.
  const CarRegionOptions options;
  cv::Mat grown;
  const int side = 2 * options.margin_px + 1 + 2 * options.window_px;
  cv::dilate(bonnet, grown, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side)));
  cv::Mat beyond;
  cv::bitwise_and(region, ~grown, beyond);
  EXPECT_EQ(cv::countNonZero(beyond), 0);
  EXPECT_LT(mask_share(region), mask_share(grown));
}

TEST(CarRegion, FindsNothingWhenEverythingMovesOrNothingDoes) {
  // A road with no bonnet: nothing.
  EXPECT_TRUE(car_region_from_frames(road_frames(8, {})).empty());
  // A car standing still: everything is still, which is no car.
  const std::vector<cv::Mat> standing(8, road_frames(1, {}).front());
  EXPECT_TRUE(car_region_from_frames(standing).empty());
  // Plain sky above a moving road: no texture, nothing.
  std::vector<cv::Mat> frames = road_frames(8, {});
  for (cv::Mat& frame : frames) frame.rowRange(0, 80).setTo(200);
  EXPECT_TRUE(car_region_from_frames(frames).empty());
}

TEST(CarRegion, SamplesSpreadOverTheDriveAndBadInputIsRefused) {
  EXPECT_EQ(car_region_samples({0, 1, 2, 3, 4, 5, 6, 7, 8}, 3),
            (std::vector<std::size_t>{0, 4, 8}));
  EXPECT_EQ(car_region_samples({2, 5}, 16), (std::vector<std::size_t>{2, 5}));
  EXPECT_TRUE(car_region_samples({}, 16).empty());
  EXPECT_THROW(car_region_from_frames({cv::Mat(10, 10, CV_8U)}), std::invalid_argument);
  EXPECT_THROW(car_region_from_frames({cv::Mat(10, 10, CV_8U), cv::Mat(10, 12, CV_8U)}),
               std::invalid_argument);
  CarRegionOptions options;
  options.max_share = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera
