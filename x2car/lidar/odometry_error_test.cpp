#include "x2car/lidar/odometry_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "x2car/core/rotation.hpp"

namespace x2car::lidar {
namespace {

// Poses every 5 cm along a path that turns at `curvature` [1/m] (0: straight along x); dense, so
// that a segment overshoots its length by at most 5 cm (KITTI divides by the nominal length).
std::vector<Eigen::Isometry3d> path(double length_m, double curvature = 0.0) {
  constexpr double kSpacing = 0.05;  // [m]
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k * kSpacing <= length_m + 1e-9; ++k) {
    const double s = k * kSpacing;
    const double heading = curvature * s;
    const Eigen::Vector3d position =
        curvature == 0.0
            ? Eigen::Vector3d(s, 0, 0)
            : Eigen::Vector3d(std::sin(heading), 1.0 - std::cos(heading), 0) / curvature;
    poses.push_back(make_transform(EulerAngles{0, 0, heading}, position));
  }
  return poses;
}

TEST(RelativeDrift, AStraightPathScaledByOnePercentDriftsOnePercent) {
  const auto truth = path(300.0);
  auto estimate = truth;
  for (auto& pose : estimate) pose.translation() *= 1.01;
  const Drift drift = relative_drift(estimate, truth);
  EXPECT_EQ(drift.per_length.size(), 4u);
  EXPECT_GT(drift.segments, 0u);
  EXPECT_NEAR(drift.translation_percent, 1.0, 2e-3);
  EXPECT_NEAR(drift.rotation_deg_per_100m, 0.0, 1e-9);
  EXPECT_EQ(drift.per_length[3].segments, 0u);  // 400 m does not fit in 300 m
  EXPECT_TRUE(std::isnan(drift.per_length[3].translation_percent));
  EXPECT_NEAR(drift.path_length_m, 300.0, 1e-9);
}

TEST(RelativeDrift, AHeadingThatDriftsOneDegreePer100MetresReadsSo) {
  const auto truth = path(300.0, 1.0 / 80.0);
  auto estimate = truth;
  const double rate = rad_from_deg(1.0) / 100.0;  // [rad/m]
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    // Rotating each pose about its own origin: relative headings drift at `rate`.
    const double s = 0.05 * static_cast<double>(i);
    estimate[i].linear() =
        estimate[i].linear() * Eigen::AngleAxisd(rate * s, Eigen::Vector3d::UnitZ()).matrix();
  }
  const Drift drift = relative_drift(estimate, truth);
  EXPECT_NEAR(drift.rotation_deg_per_100m, 1.0, 2e-3);
}

TEST(RelativeDrift, SameTrajectoryHasNoDriftAndMismatchedSizesThrow) {
  const auto truth = path(120.0, 1.0 / 40.0);
  EXPECT_NEAR(relative_drift(truth, truth).translation_percent, 0.0, 1e-12);
  const auto shorter = path(100.0);
  EXPECT_THROW(relative_drift(shorter, truth), std::invalid_argument);
  const Drift none = relative_drift(path(20.0), path(20.0));
  EXPECT_EQ(none.segments, 0u);
  EXPECT_TRUE(std::isnan(none.translation_percent));
  DriftOptions bad;
  bad.step = 0;
  EXPECT_THROW(relative_drift(truth, truth, bad), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::lidar
