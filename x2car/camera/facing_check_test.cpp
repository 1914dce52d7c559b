#include "x2car/camera/facing_check.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera {
namespace {

const core::CameraIntrinsics kCamera = core::camera_preset("kitti");

// Frames down a textured road, `step_m` a frame, seen from `mounting`; pairs of each frame with
// the next.
struct RoadFrames {
  std::vector<cv::Mat> images;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
};

RoadFrames road_frames(const EulerAngles& mounting, double step_m, std::size_t count = 6) {
  RoadFrames frames;
  for (std::size_t i = 0; i < count; ++i) {
    frames.images.push_back(
        testing::road_picture(mounting, kCamera, step_m * static_cast<double>(i)));
    if (i > 0) frames.pairs.emplace_back(i - 1, i);
  }
  return frames;
}

// The vanishing point a vanishing-point method finds for `mounting`: that of the car's x axis for
// a camera that looks ahead, of its -x axis for one that looks back (the same image point).
Eigen::Vector2d vanishing_point_of(EulerAngles mounting) {
  if (std::abs(mounting.yaw) > kPi / 2) mounting.yaw = wrap_angle(mounting.yaw + kPi);
  return vanishing_geometry_from_rotation(rotation_from_euler(mounting), kCamera.camera_matrix())
      ->vanishing_point_px;
}

FacingCheck check(const RoadFrames& frames, const EulerAngles& mounting) {
  return check_facing([&](std::size_t i) { return frames.images[i]; }, frames.pairs, kCamera,
                      vanishing_point_of(mounting), cv::Mat());
}

TEST(FacingCheck, TheSceneFlowsOutOfTheVanishingPointAheadAndIntoItBehind) {
  const EulerAngles ahead{rad_from_deg(0.5), rad_from_deg(3.0), rad_from_deg(1.0)};
  const FacingCheck looking_ahead = check(road_frames(ahead, 1.0), ahead);
  EXPECT_EQ(looking_ahead.facing, Facing::kAhead);
  EXPECT_EQ(looking_ahead.pairs, 5U);
  EXPECT_EQ(looking_ahead.expanding, 5U);

  const EulerAngles back{rad_from_deg(0.5), rad_from_deg(3.0), wrap_angle(kPi + rad_from_deg(1.0))};
  const FacingCheck looking_back = check(road_frames(back, 1.0), back);
  EXPECT_EQ(looking_back.facing, Facing::kBack);
  EXPECT_EQ(looking_back.contracting, 5U);
}

// The car's own bonnet over the image's bottom stays put while the road moves: its corners are
// left out of the pairs' medians (enough of them held the median at 0, and a rear camera's bumper
// would have been taken as looking ahead).
TEST(FacingCheck, CornersThatStayPutDoNotVote) {
  const EulerAngles back{0.0, rad_from_deg(3.0), wrap_angle(kPi + rad_from_deg(1.0))};
  RoadFrames frames = road_frames(back, 1.0);
  const cv::Mat bonnet = testing::bonnet_shape(frames.images.front().size(), 0.45);
  for (cv::Mat& image : frames.images) testing::paint_bonnet(image, bonnet);
  const FacingCheck looking_back = check(frames, back);
  EXPECT_EQ(looking_back.facing, Facing::kBack);
  EXPECT_EQ(looking_back.contracting, 5U);
}

TEST(FacingCheck, ACarStandingStillDecidesNothing) {
  const EulerAngles ahead{0.0, rad_from_deg(3.0), 0.0};
  const FacingCheck standing = check(road_frames(ahead, 0.0, 4), ahead);
  EXPECT_EQ(standing.facing, Facing::kUndecided);
  EXPECT_EQ(standing.expanding + standing.contracting, 0U);
}

TEST(FacingCheck, SamplesEvenlyInOrderAndSkipsUnreadableFrames) {
  const EulerAngles ahead{0.0, rad_from_deg(3.0), 0.0};
  const RoadFrames frames = road_frames(ahead, 1.0, 8);
  std::vector<std::size_t> read;
  FacingCheckOptions options;
  options.frame_pairs = 3;
  options.min_moving_pairs = 2;
  const FacingCheck sampled = check_facing(
      [&](std::size_t i) {
        read.push_back(i);
        return i == 7 ? cv::Mat() : frames.images[i];
      },
      frames.pairs, kCamera, vanishing_point_of(ahead), cv::Mat(), options);
  // Pairs 0, 3 and 6 of the 7: frames 0-1, 3-4, 6-7 in order; the last has no image.
  EXPECT_EQ(read, (std::vector<std::size_t>{0, 1, 3, 4, 6, 7}));
  EXPECT_EQ(sampled.pairs, 3U);
  EXPECT_EQ(sampled.expanding, 2U);
  EXPECT_EQ(sampled.facing, Facing::kAhead);
  options.min_agreement = 0.4;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera
