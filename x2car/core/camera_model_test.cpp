#include "x2car/core/camera_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace x2car::core {
namespace {

using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;

// Every pixel of the image on a grid `step` px apart (and the last row and column).
template <typename Visit>
void for_grid(const CameraIntrinsics& c, double step, Visit visit) {
  for (double v = 0.0;; v = std::min(v + step, c.height - 1.0)) {
    for (double u = 0.0;; u = std::min(u + step, c.width - 1.0)) {
      visit(Eigen::Vector2d(u, v));
      if (u == c.width - 1.0) break;
    }
    if (v == c.height - 1.0) break;
  }
}

TEST(CameraModel, DefaultIsKittisRectifiedFrontCamera) {
  const CameraIntrinsics c;
  EXPECT_EQ(c, camera_preset("kitti"));
  EXPECT_NO_THROW(c.Check());
  EXPECT_EQ(c.width, 1242);
  EXPECT_EQ(c.height, 375);
  EXPECT_EQ(c.fx, 721.5377);
  EXPECT_EQ(c.cy, 172.854);
  EXPECT_EQ(c.distortion_model, DistortionModel::kNone);
  EXPECT_EQ(c.camera_matrix()(0, 2), c.cx);
  EXPECT_EQ(c.camera_matrix()(1, 1), c.fy);
}

TEST(CameraModel, PresetsHaveTheirFieldsOfView) {
  // Horizontal field of view from the rays of the left and right edges through the centre row.
  const auto hfov_deg = [](const CameraIntrinsics& c) {
    const Eigen::Vector3d left = pixel_to_ray(c, {-0.5, c.cy});
    const Eigen::Vector3d right = pixel_to_ray(c, {c.width - 0.5, c.cy});
    return std::acos(left.dot(right)) * 180.0 / kPi;
  };
  EXPECT_NEAR(hfov_deg(camera_preset("kitti")), 81.2, 0.5);
  EXPECT_NEAR(hfov_deg(camera_preset("automotive_1080p")), 82.0, 3.0);  // 77 deg before distortion
  EXPECT_NEAR(hfov_deg(camera_preset("dashcam_wide")), 120.0, 2.0);
  EXPECT_THAT(camera_preset_names(),
              ::testing::ElementsAre("kitti", "automotive_1080p", "dashcam_wide"));
  for (const std::string& name : camera_preset_names()) {
    EXPECT_NO_THROW(camera_preset(name).Check()) << name;
    EXPECT_NO_THROW(check_every_pixel_has_a_ray(camera_preset(name))) << name;
  }
  try {
    camera_preset("gopro");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("dashcam_wide"));
  }
}

TEST(CameraModel, EveryPixelOfEveryPresetRoundTripsThroughItsRay) {
  for (const std::string& name : camera_preset_names()) {
    const CameraIntrinsics c = camera_preset(name);
    double worst_px = 0.0;
    for_grid(c, 7.0, [&](const Eigen::Vector2d& pixel) {
      const Eigen::Vector3d ray = pixel_to_ray(c, pixel);
      ASSERT_NEAR(ray.norm(), 1.0, 1e-12);
      ASSERT_GT(ray.z(), 0.0);
      const auto back = project_to_pixel(c, 3.7 * ray);
      ASSERT_TRUE(back.has_value()) << name << " " << pixel.transpose();
      worst_px = std::max(worst_px, (*back - pixel).norm());
      // The normalised-coordinate pair agrees with the ray.
      const auto undistorted =
          undistort_normalized(c, {(pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy});
      ASSERT_TRUE(undistorted.has_value());
      ASSERT_NEAR((*undistorted - ray.head<2>() / ray.z()).norm(), 0.0, 1e-9);
      const Eigen::Vector2d pinhole = undistort_pixel(c, pixel);
      ASSERT_NEAR(pinhole.x(), c.fx * ray.x() / ray.z() + c.cx, 1e-6);
    });
    EXPECT_LT(worst_px, 0.01) << name;
  }
}

TEST(CameraModel, KnownPointsLandOnTheirPixels) {
  // Plumb bob by hand: x = (0.2, -0.1), r^2 = 0.05.
  CameraIntrinsics c = camera_preset("automotive_1080p");
  c.distortion_coefficients = {-0.2, 0.05, 0.001, -0.002, 0.01};
  const double r2 = 0.05, radial = 1.0 - 0.2 * r2 + 0.05 * r2 * r2 + 0.01 * r2 * r2 * r2;
  const double xd = 0.2 * radial + 2 * 0.001 * 0.2 * -0.1 + -0.002 * (r2 + 2 * 0.04);
  const double yd = -0.1 * radial + 0.001 * (r2 + 2 * 0.01) + 2 * -0.002 * 0.2 * -0.1;
  const auto pixel = project_to_pixel(c, Eigen::Vector3d(0.2, -0.1, 1.0) * 12.0);
  ASSERT_TRUE(pixel.has_value());
  EXPECT_NEAR(pixel->x(), 1200.0 * xd + 959.5, 1e-9);
  EXPECT_NEAR(pixel->y(), 1200.0 * yd + 539.5, 1e-9);
  EXPECT_NEAR((pixel_to_ray(c, *pixel) - Eigen::Vector3d(0.2, -0.1, 1.0).normalized()).norm(), 0.0,
              1e-10);

  // Equidistant by hand: a ray 45 deg off axis to the right lands at f theta_d right of centre.
  c = camera_preset("dashcam_wide");
  const double theta = kPi / 4, t2 = theta * theta;
  const double theta_d = theta * (1 + 0.03 * t2 - 0.005 * t2 * t2 + 0.001 * std::pow(t2, 3) -
                                  0.0002 * std::pow(t2, 4));
  const auto wide = project_to_pixel(c, {5.0, 0.0, 5.0});
  ASSERT_TRUE(wide.has_value());
  EXPECT_NEAR(wide->x(), 639.5 + 595.0 * theta_d, 1e-9);
  EXPECT_NEAR(wide->y(), 359.5, 1e-12);

  // Without distortion: the pinhole.
  c = CameraIntrinsics{};
  const auto kitti = project_to_pixel(c, {-1.0, 0.5, 20.0});
  ASSERT_TRUE(kitti.has_value());
  EXPECT_NEAR(kitti->x(), 609.5593 - 721.5377 / 20.0, 1e-12);
  EXPECT_NEAR(kitti->y(), 172.854 + 721.5377 / 40.0, 1e-12);
  EXPECT_NEAR(pixel_to_ray(c, {c.cx, c.cy}).z(), 1.0, 1e-15);  // the principal ray
}

TEST(CameraModel, PointsBehindOrBeyondTheModelHaveNoPixel) {
  const CameraIntrinsics kitti;
  EXPECT_FALSE(project_to_pixel(kitti, {0.0, 0.0, -1.0}).has_value());
  EXPECT_FALSE(project_to_pixel(kitti, {1.0, 0.0, 0.0}).has_value());
  // Strong barrel plumb bob: the radial slope 1 - 0.9 r^2 turns negative at r = 1.05; a point
  // beyond would fold back onto the image.
  CameraIntrinsics barrel = camera_preset("automotive_1080p");
  barrel.distortion_coefficients = {-0.3, 0.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(project_to_pixel(barrel, {1.0, 0.0, 1.0}).has_value());
  EXPECT_FALSE(project_to_pixel(barrel, {1.1, 0.0, 1.0}).has_value());
  // Its distorted radius peaks at 0.703; beyond, undistortion has no solution.
  EXPECT_FALSE(undistort_normalized(barrel, {0.75, 0.0}).has_value());
  const Eigen::Vector3d ray = pixel_to_ray(barrel, {959.5 + 0.75 * 1200, 539.5});
  EXPECT_TRUE(ray.allFinite());  // the best iterate, not NaN
  EXPECT_THROW(check_every_pixel_has_a_ray(barrel), std::invalid_argument);
  // Equidistant rays 90 deg off axis have no normalised coordinates.
  const CameraIntrinsics wide = camera_preset("dashcam_wide");
  EXPECT_FALSE(undistort_normalized(wide, {2.0, 0.0}).has_value());  // theta_d(90 deg) = 1.66
}

TEST(CameraModel, CheckRejectsImpossibleCameras) {
  CameraIntrinsics bad;
  bad.fx = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.cx = 2500.0;  // outside the 1242 px image
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.distortion_coefficients = {0.1};  // the "none" model has none
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = camera_preset("dashcam_wide");
  bad.distortion_coefficients.push_back(0.0);  // equidistant has 4
  try {
    bad.Check();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("4 coefficients of the equidistant model"));
  }
  EXPECT_EQ(distortion_model_from_string("equidistant"), DistortionModel::kEquidistant);
  EXPECT_EQ(to_string(DistortionModel::kPlumbBob), "plumb_bob");
  EXPECT_THROW(distortion_model_from_string("fisheye"), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::core
