#include "x2car/camera_net/network_input.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <opencv2/imgproc.hpp>

#include "x2car/camera_net/network_metrics.hpp"
#include "x2car/camera_net/training_data.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera_net {
namespace {

TEST(NetworkInput, PlanePointsAndPixelsRoundTrip) {
  const InputGeometry geometry;
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(311.5, 47.25), Eigen::Vector2d(511, 159)}) {
    EXPECT_LT((geometry.input_pixel(geometry.plane_point(pixel)) - pixel).norm(), 1e-9);
    EXPECT_LT((geometry.input_pixel(3.0 * geometry.plane_point(pixel)) - pixel).norm(), 1e-9);
  }
  // The centre of the image is the plane's origin; one scale on both axes.
  EXPECT_LT((geometry.plane_point({255.5, 79.5}) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_NEAR(geometry.plane_point({255.5 + 256.0, 79.5 + 256.0}).y(), 1.0, 1e-12);
}

TEST(NetworkInput, ImageAndInputPixelsAndAnglesRoundTrip) {
  const InputGeometry geometry;
  const cv::Size image(1242, 375);
  const Eigen::Vector2d pixel(609.6, 172.9);
  EXPECT_LT(
      (image_from_input_px(input_from_image_px(pixel, image, geometry), image, geometry) - pixel)
          .norm(),
      1e-9);
  // The image's centre maps to the input's.
  EXPECT_LT(
      (input_from_image_px({620.5, 187.0}, image, geometry) - Eigen::Vector2d(255.5, 79.5)).norm(),
      1e-9);
  for (const double angle : {-0.3, -0.01, 0.0, 0.02, 0.4}) {
    const double input_angle = input_from_image_angle(angle, image, geometry);
    EXPECT_NEAR(image_from_input_angle(input_angle, image, geometry), angle, 1e-12);
    // Each axis scaled on its own: tan scales by (height ratio) / (width ratio).
    EXPECT_NEAR(std::tan(input_angle), std::tan(angle) * (160.0 / 375.0) / (512.0 / 1242.0), 1e-12);
  }
}

TEST(NetworkInput, StructureTensorIsTheUpperTriangleOfTheLinesOuterProduct) {
  const Eigen::Vector3d line(0.3, -0.8, 0.5);
  const std::array<float, 6> tensor = line_structure_tensor(line);
  const std::array<float, 6> flipped = line_structure_tensor(-2.0 * line);
  const Eigen::Vector3d l = line.normalized();
  const std::array<double, 6> expected = {l[0] * l[0], l[0] * l[1], l[1] * l[1],
                                          l[0] * l[2], l[1] * l[2], l[2] * l[2]};
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(tensor[i], expected[i], 1e-6);
    EXPECT_EQ(tensor[i], flipped[i]);  // the same line, whatever its sign and scale
  }
}

TEST(NetworkInput, LinesThroughTheVanishingPointAreClassedThrough) {
  const InputGeometry geometry;
  const Eigen::Vector2d vp(300.0, 60.0);
  const Eigen::Vector3d vanishing = geometry.plane_point(vp).normalized();
  const InputSegment towards{{100.0, 150.0}, {200.0, 105.0}};  // on the line to the VP
  const InputSegment across{{100.0, 150.0}, {200.0, 150.0}};
  EXPECT_TRUE(passes_through(plane_line(towards, geometry), vanishing, 0.02));
  EXPECT_FALSE(passes_through(plane_line(across, geometry), vanishing, 0.02));
}

TEST(NetworkInput, SegmentSamplingIsSeededAndKeepsEverySegmentWhenFew) {
  std::vector<InputSegment> segments;
  for (int i = 0; i < 50; ++i) segments.push_back({{0.0, 0.0}, {1.0 + i, 0.0}});
  EXPECT_EQ(sample_segments(segments, 64, 1).size(), 50u);
  const std::vector<int> first = sample_segments(segments, 10, 7);
  EXPECT_EQ(first.size(), 10u);
  EXPECT_EQ(first, sample_segments(segments, 10, 7));
  EXPECT_NE(first, sample_segments(segments, 10, 8));
  EXPECT_TRUE(std::is_sorted(first.begin(), first.end()));
  // Longer segments are likelier: over many seeds the longest half wins most places.
  int long_ones = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    for (const int index : sample_segments(segments, 10, seed)) long_ones += index >= 25 ? 1 : 0;
  }
  EXPECT_GT(long_ones, 1200);  // of 2000
}

// The augmented label must describe the augmented image: a bright dot drawn at the vanishing
// point lands where the augmented label says, through a flip, a rotation, a scaling and a shift;
// the horizon turns with the image, a flip mirrors it and a shift leaves it.
TEST(NetworkInput, AugmentationMovesTheImageAndItsLabelsAlike) {
  const InputGeometry geometry;
  InputFrame frame;
  frame.grey = cv::Mat(geometry.height, geometry.width, CV_8UC1, cv::Scalar(40));
  const Eigen::Vector2d vp(300.0, 60.0);
  cv::circle(frame.grey, cv::Point(300, 60), 3, cv::Scalar(255), cv::FILLED);
  frame.segments.push_back({{100.0, 150.0}, {200.0, 105.0}});
  const InputLabel label{vp, 0.05};
  for (const Augmentation& augmentation :
       {Augmentation{false, 0.0, 1.0}, Augmentation{true, 0.0, 1.0},
        Augmentation{false, rad_from_deg(5.0), 1.0}, Augmentation{true, rad_from_deg(-4.0), 1.1},
        Augmentation{false, rad_from_deg(3.0), 0.9},
        Augmentation{false, 0.0, 1.0, Eigen::Vector2d(-20.5, 11.0)},
        Augmentation{true, rad_from_deg(2.0), 1.05, Eigen::Vector2d(17.0, -9.25)}}) {
    InputFrame augmented;
    InputLabel moved;
    augment(frame, label, augmentation, geometry, augmented, moved);
    // The dot's centre of brightness above the background.
    cv::Mat dot;
    cv::subtract(augmented.grey, cv::Scalar(40), dot);
    const cv::Moments moments = cv::moments(dot);
    const Eigen::Vector2d centre(moments.m10 / moments.m00, moments.m01 / moments.m00);
    EXPECT_LT((centre - moved.vanishing_point_px).norm(), 0.25)
        << "flip " << augmentation.flip << " rotation " << augmentation.rotation_rad;
    const double expected_angle = (augmentation.flip ? -label.horizon_angle : label.horizon_angle) +
                                  augmentation.rotation_rad;
    EXPECT_NEAR(moved.horizon_angle, expected_angle, 1e-12);
    // The segment still points at the vanishing point.
    EXPECT_TRUE(passes_through(plane_line(augmented.segments.front(), geometry),
                               geometry.plane_point(moved.vanishing_point_px).normalized(), 1e-9));
  }
}

TEST(NetworkMetrics, PerfectPredictionsScorePerfectly) {
  const InputGeometry geometry;
  const std::vector<InputLabel> labels = {{{250.0, 70.0}, 0.01}, {{270.0, 90.0}, -0.02}};
  std::vector<NetworkPrediction> predictions(2);
  for (std::size_t i = 0; i < 2; ++i) {
    predictions[i].vanishing_direction =
        geometry.plane_point(labels[i].vanishing_point_px).normalized();
    predictions[i].horizon_angle = labels[i].horizon_angle;
  }
  const NetworkMetrics perfect = score_predictions(labels, predictions, {}, geometry);
  EXPECT_LT(perfect.vp_error_px_mean, 1e-9);
  EXPECT_LT(perfect.hl_angle_mse, 1e-20);
  EXPECT_NEAR(perfect.hl_auc, 1.0, 1e-12);
  // The guess without the image: the input's centre (255.5, 79.5) and a level horizon.
  EXPECT_NEAR(perfect.centre_vp_error_px_mean,
              0.5 * (std::hypot(5.5, 9.5) + std::hypot(14.5, 10.5)), 1e-9);
  EXPECT_NEAR(perfect.level_hl_angle_mse, 0.5 * (0.01 * 0.01 + 0.02 * 0.02), 1e-15);

  // A horizon 8 px too low at a 160-px image: error 0.05 of the height, AUC 0.8 for that frame.
  predictions[1].vanishing_direction = geometry.plane_point({270.0, 98.0}).normalized();
  const NetworkMetrics off = score_predictions(labels, predictions, {}, geometry);
  EXPECT_NEAR(off.vp_error_px_mean, 4.0, 1e-9);
  EXPECT_NEAR(off.hl_auc, 0.9, 1e-9);
}

TEST(TrainingData, LabelsWithoutTheirColumnsAreRefusedNamingTheColumn) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "camera_net_labels_missing.csv";
  io::write_text_file(path, "time,road_vp_u_distorted,road_horizon_angle\n0,1,2\n");
  try {
    read_frame_labels(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("road_vp_v_distorted"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("camera_net_labels_missing.csv"), std::string::npos);
  }
  io::write_text_file(path,
                      "time,road_vp_u_distorted,road_vp_v_distorted,road_horizon_angle\n"
                      "0,600,170,0.01\n0.1,601,x,0.01\n");
  try {
    read_frame_labels(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(":3"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace x2car::camera_net
