#include "x2car/camera/car_region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"

namespace x2car::camera {
namespace {

const core::CameraIntrinsics& camera() {
  static const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  return intrinsics;
}

// Frames of a road driven along (the road's texture moves), with sensor noise on every frame.
std::vector<cv::Mat> road_frames(int count, const cv::Mat& bonnet) {
  const EulerAngles mounting{0.0, rad_from_deg(1.0), 0.0};
  std::vector<cv::Mat> frames;
  for (int i = 0; i < count; ++i) {
    cv::Mat image = testing::road_picture(mounting, camera(), 7.0 * i);
    if (!bonnet.empty()) testing::paint_bonnet(image, bonnet);
    cv::Mat grain(image.size(), CV_16S);
    cv::randn(grain, 0.0, 1.5);
    cv::Mat noisy;
    image.convertTo(noisy, CV_16S);
    noisy += grain;
    noisy.convertTo(image, CV_8U);
    frames.push_back(image);
  }
  return frames;
}

TEST(CarRegion, FindsABonnetThatStaysWhileTheRoadMoves) {
  const cv::Size size(camera().width, camera().height);
  const cv::Mat bonnet = testing::bonnet_shape(size, 0.15);
  const cv::Mat region = car_region_from_frames(road_frames(8, bonnet));
  ASSERT_FALSE(region.empty());
  // All of the bonnet, grown by the margin and no more (but for a few pixels where the solid lane
  // line, static too on a straight road, meets it).
  cv::Mat missed;
  cv::bitwise_and(bonnet, ~region, missed);
  EXPECT_EQ(cv::countNonZero(missed), 0);
  cv::Mat grown;
  const CarRegionOptions options;
  const int side = 2 * (options.margin_px + 4) + 1;
  cv::dilate(bonnet, grown, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side)));
  cv::Mat beyond;
  cv::bitwise_and(region, ~grown, beyond);
  EXPECT_EQ(cv::countNonZero(beyond), 0);
  EXPECT_NEAR(mask_share(region), mask_share(bonnet), 0.05);
}

TEST(CarRegion, FindsNothingWhenEverythingMovesOrNothingDoes) {
  // A road with no bonnet: nothing.
  EXPECT_TRUE(car_region_from_frames(road_frames(8, {})).empty());
  // A car standing still: everything is static, which is no car.
  const std::vector<cv::Mat> standing(8, road_frames(1, {}).front());
  EXPECT_TRUE(car_region_from_frames(standing).empty());
  // Plain static sky above a moving road, and plain static asphalt below: no texture, no car.
  std::vector<cv::Mat> frames = road_frames(8, {});
  for (cv::Mat& frame : frames) {
    frame.rowRange(0, 80).setTo(200);
    frame.rowRange(frame.rows - 40, frame.rows).setTo(70);
  }
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
