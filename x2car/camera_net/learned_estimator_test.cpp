#include "x2car/camera_net/learned_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "x2car/core/camera_model.hpp"

namespace x2car::camera_net {
namespace {

// A KITTI-sized camera with barrel distortion, a road direction, and the segments a network
// would see at its 512 x 160 input: `through` of them on 3-D lines along the road (drawn through
// the distortion, so in the raw image they bend towards its edges), the rest in random
// directions.
struct NetworkView {
  core::CameraIntrinsics intrinsics;
  Eigen::Vector3d road_direction;
  InputGeometry input;
  InputFrame frame;
  std::vector<int> chosen;
};

NetworkView network_view(int through, int others) {
  NetworkView view;
  view.intrinsics = core::camera_preset("kitti");
  view.intrinsics.distortion_model = core::DistortionModel::kPlumbBob;
  view.intrinsics.distortion_coefficients = {-0.3, 0.1, 0.0, 0.0, 0.0};
  view.road_direction = Eigen::Vector3d(-0.12, 0.06, 1.0).normalized();
  const cv::Size image_size(view.intrinsics.width, view.intrinsics.height);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> lateral(-6.0, 6.0), height(-1.0, 4.0), ahead(8.0, 40.0),
      input_u(0.0, 512.0), input_v(0.0, 160.0), angle(0.0, 2.0 * M_PI);
  while (static_cast<int>(view.frame.segments.size()) < through) {
    // Short 3-D pieces (2 m) of lines along the road: nearly straight in the raw image too.
    const Eigen::Vector3d start(lateral(random), height(random), ahead(random));
    const std::optional<Eigen::Vector2d> a = core::project_to_pixel(view.intrinsics, start);
    const std::optional<Eigen::Vector2d> b =
        core::project_to_pixel(view.intrinsics, start + 2.0 * view.road_direction);
    if (!a || !b || a->x() < 0 || a->x() > image_size.width || a->y() < 0 ||
        a->y() > image_size.height || (*b - *a).norm() < 25.0) {
      continue;
    }
    view.frame.segments.push_back({input_from_image_px(*a, image_size, view.input),
                                   input_from_image_px(*b, image_size, view.input)});
  }
  for (int i = 0; i < others; ++i) {
    const Eigen::Vector2d start(input_u(random), input_v(random));
    const double turn = angle(random);
    view.frame.segments.push_back(
        {start, start + 20.0 * Eigen::Vector2d(std::cos(turn), std::sin(turn))});
  }
  // The queries in another order than the segments (the batch samples them).
  for (int i = through + others - 1; i >= 0; --i) view.chosen.push_back(i);
  return view;
}

// The undistorted pixel of the road's vanishing point.
Eigen::Vector2d road_vanishing_point(const NetworkView& view) {
  return (view.intrinsics.camera_matrix() * view.road_direction).hnormalized();
}

// Each query's probability: 0.9 for the segments along the road (the first `through`), else 0.1.
std::vector<float> right_about_the_lines(const NetworkView& view, int through) {
  std::vector<float> probability;
  for (const int segment : view.chosen) probability.push_back(segment < through ? 0.9f : 0.1f);
  return probability;
}

TEST(LearnedEstimator, TheNetworksVanishingPointIsRefinedOnTheLinesItSaysPassThroughIt) {
  const NetworkView view = network_view(10, 15);
  const cv::Size image_size(view.intrinsics.width, view.intrinsics.height);
  // The network right about which lines pass through it, and 15 px off in its vanishing point
  // (about its error at full resolution): the lines' vanishing point, exactly.
  const std::vector<float> probability = right_about_the_lines(view, 10);
  const Eigen::Vector2d network_vp = road_vanishing_point(view) + Eigen::Vector2d(12.0, -9.0);
  const std::optional<camera::DirectionFit> refined = refine_on_lines_through(
      view.frame, view.chosen, probability, image_size, view.intrinsics, view.input, network_vp);
  ASSERT_TRUE(refined.has_value());
  const Eigen::Vector2d refined_vp =
      (view.intrinsics.camera_matrix() * refined->direction).hnormalized();
  EXPECT_LT((refined_vp - road_vanishing_point(view)).norm(), 1e-6)
      << refined_vp.transpose() << " vs " << road_vanishing_point(view).transpose();
  EXPECT_EQ(refined->inliers.size(), 10U);
  // Without undistorting the segments' ends, the bent lines would miss it by pixels; the test
  // camera's distortion is large enough to tell.
  NetworkView pinhole = view;
  pinhole.intrinsics.distortion_model = core::DistortionModel::kNone;
  pinhole.intrinsics.distortion_coefficients.clear();
  const std::optional<camera::DirectionFit> unbent =
      refine_on_lines_through(pinhole.frame, pinhole.chosen, probability, image_size,
                              pinhole.intrinsics, pinhole.input, network_vp);
  ASSERT_TRUE(unbent.has_value());
  const Eigen::Vector2d unbent_vp =
      (pinhole.intrinsics.camera_matrix() * unbent->direction).hnormalized();
  EXPECT_GT((unbent_vp - road_vanishing_point(view)).norm(), 2.0);
}

TEST(LearnedEstimator, LinesTheNetworkDoesNotTrustLeaveItsVanishingPoint) {
  const NetworkView view = network_view(10, 15);
  const cv::Size image_size(view.intrinsics.width, view.intrinsics.height);
  const Eigen::Vector2d network_vp = road_vanishing_point(view) + Eigen::Vector2d(12.0, -9.0);
  // No line above the probability: nothing to refine on.
  const std::vector<float> doubtful(view.chosen.size(), 0.3f);
  EXPECT_FALSE(refine_on_lines_through(view.frame, view.chosen, doubtful, image_size,
                                       view.intrinsics, view.input, network_vp));
  // Fewer probabilities than queries (a padded batch): only those are read.
  std::vector<float> three(3, 0.9f);
  EXPECT_FALSE(refine_on_lines_through(view.frame, view.chosen, three, image_size, view.intrinsics,
                                       view.input, network_vp));
  // The options' threshold decides which lines count.
  LearnedEstimatorOptions strict;
  strict.line_through_probability = 0.95;
  const std::vector<float> probability = right_about_the_lines(view, 10);
  EXPECT_FALSE(refine_on_lines_through(view.frame, view.chosen, probability, image_size,
                                       view.intrinsics, view.input, network_vp, strict));
  EXPECT_TRUE(refine_on_lines_through(view.frame, view.chosen, probability, image_size,
                                      view.intrinsics, view.input, network_vp));
}

TEST(LearnedEstimator, RefinementOptionsAreChecked) {
  LearnedEstimatorOptions options;
  EXPECT_NO_THROW(options.Check());
  options.line_through_probability = 1.5;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.refinement.min_inliers = 1;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.standard_error_floor.pitch = -0.1;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera_net
