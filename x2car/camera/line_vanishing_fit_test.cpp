#include "x2car/camera/line_vanishing_fit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "x2car/core/camera_model.hpp"

namespace x2car::camera {
namespace {

// A direction `angle` away from `direction`, turned about the optical frame's y axis (in yaw).
Eigen::Vector3d yawed(const Eigen::Vector3d& direction, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()) * direction;
}

struct Scene {
  Eigen::Matrix3d camera_matrix;
  Eigen::Vector3d road_direction;
  std::vector<ImageSegment> segments;
  int through = 0;  // the first `through` segments pass through the road's vanishing point
};

// `through` segments of 20-80 px exactly on lines through the road's vanishing point, spread over
// a KITTI-sized image, and `others` in random directions (a network's wrong classifications).
Scene scene(int through, int others, std::uint64_t seed) {
  Scene s;
  s.camera_matrix = core::camera_preset("kitti").camera_matrix();
  s.road_direction = Eigen::Vector3d(0.06, -0.035, 1.0).normalized();
  s.through = through;
  const Eigen::Vector2d vanishing_px = (s.camera_matrix * s.road_direction).hnormalized();
  const Eigen::Matrix3d transposed = s.camera_matrix.transpose();
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> u(0.0, 1242.0), v(0.0, 375.0), length(20.0, 80.0),
      angle(0.0, 2.0 * M_PI);
  for (int i = 0; i < through + others; ++i) {
    Eigen::Vector2d start(u(random), v(random));
    if ((start - vanishing_px).norm() < 100.0) start = vanishing_px + Eigen::Vector2d(150.0, 90.0);
    const Eigen::Vector2d along =
        i < through ? Eigen::Vector2d((vanishing_px - start).normalized())
                    : Eigen::Vector2d(std::cos(angle(random)), std::sin(angle(random)));
    s.segments.push_back(image_segment(start, start + length(random) * along, transposed));
  }
  return s;
}

TEST(LineVanishingFit, AGuessIsRefinedOntoTheLinesThroughItsVanishingPoint) {
  const Scene s = scene(12, 20, 1);
  for (const double guess_error_deg : {-3.0, -1.0, 0.5, 2.0}) {
    const std::optional<DirectionFit> fit = refine_vanishing_guess(
        s.segments, s.camera_matrix, yawed(s.road_direction, rad_from_deg(guess_error_deg)), {});
    ASSERT_TRUE(fit.has_value()) << guess_error_deg;
    EXPECT_LT(std::acos(std::min(1.0, fit->direction.dot(s.road_direction))), 1e-6)
        << guess_error_deg;
    // Every segment through it, and of the random ones at most a few that point at it by chance.
    int true_inliers = 0;
    for (const int index : fit->inliers) true_inliers += index < s.through ? 1 : 0;
    EXPECT_EQ(true_inliers, s.through);
    EXPECT_LE(fit->inliers.size(), static_cast<std::size_t>(s.through + 3));
  }
}

TEST(LineVanishingFit, WhatTheLinesDoNotCarryIsNotRefined) {
  // Too few lines through it.
  const Scene few = scene(3, 0, 2);
  EXPECT_FALSE(refine_vanishing_guess(few.segments, few.camera_matrix, few.road_direction, {}));
  // The lines' vanishing point beyond the capture angle of the guess.
  const Scene s = scene(12, 0, 3);
  EXPECT_FALSE(refine_vanishing_guess(s.segments, s.camera_matrix,
                                      yawed(s.road_direction, rad_from_deg(8.0)), {}));
  // Within the capture angle but further than max_shift.
  VanishingRefinementOptions near;
  near.max_shift = rad_from_deg(1.0);
  EXPECT_FALSE(refine_vanishing_guess(s.segments, s.camera_matrix,
                                      yawed(s.road_direction, rad_from_deg(2.0)), near));
  EXPECT_TRUE(refine_vanishing_guess(s.segments, s.camera_matrix,
                                     yawed(s.road_direction, rad_from_deg(0.5)), near));
  // A guess behind the camera or not finite.
  EXPECT_FALSE(refine_vanishing_guess(s.segments, s.camera_matrix, -s.road_direction, {}));
  EXPECT_FALSE(
      refine_vanishing_guess(s.segments, s.camera_matrix, Eigen::Vector3d(NAN, 0.0, 1.0), {}));
}

TEST(LineVanishingFit, RejectsBadOptions) {
  const auto rejects = [](auto change, const char* field) {
    VanishingRefinementOptions options;
    change(options);
    try {
      options.Check();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(field), std::string::npos) << error.what();
    }
  };
  EXPECT_NO_THROW(VanishingRefinementOptions{}.Check());
  rejects([](VanishingRefinementOptions& o) { o.capture_angle = 0.0; }, "capture_angle");
  rejects([](VanishingRefinementOptions& o) { o.inlier_angle = 1.0; }, "inlier_angle");
  rejects([](VanishingRefinementOptions& o) { o.rounds = 0; }, "rounds");
  rejects([](VanishingRefinementOptions& o) { o.min_inliers = 1; }, "min_inliers");
  rejects([](VanishingRefinementOptions& o) { o.max_shift = -0.1; }, "max_shift");
}

}  // namespace
}  // namespace x2car::camera
