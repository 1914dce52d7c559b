#include "x2car/core/turn_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

// A sensor 1.5 m ahead of the rear axle on a 20 m radius: its velocity points asin(1.5 / 20) to
// the left of the car's x axis, whatever the speed.
TEST(TurnGeometry, ShiftIsTheAngleOfOmegaTimesTheLeverArm) {
  const std::vector<double> curvature = {0.0, 1.0 / 20.0, -1.0 / 20.0, std::nan("")};
  const std::vector<double> shift = lever_arm_heading_shift(curvature, 1.5);
  EXPECT_DOUBLE_EQ(shift[0], 0.0);
  EXPECT_NEAR(shift[1], std::asin(1.5 / 20.0), 1e-12);
  EXPECT_NEAR(shift[2], -std::asin(1.5 / 20.0), 1e-12);
  EXPECT_TRUE(std::isnan(shift[3]));
}

// Offsets psi - asin(kappa r_x) with noise and a few wild samples, over straights and turns both
// ways: the fit recovers r_x and psi.
TEST(TurnGeometry, FitsTheLeverArmAndTheYawJointly) {
  const double psi = rad_from_deg(2.0), lever_arm_x = 1.2;
  std::vector<double> times, offsets, curvature;
  for (int i = 0; i < 6000; ++i) {
    const double t = 0.01 * i;
    const double kappa = 0.06 * std::sin(2.0 * kPi * t / 15.0);
    times.push_back(t);
    curvature.push_back(kappa);
    // Deterministic noise of +-0.01 deg and an outlier every 500 samples.
    const double noise = rad_from_deg(0.01) * std::sin(12.9898 * i) + (i % 500 == 0 ? 0.05 : 0.0);
    offsets.push_back(wrap_angle(psi - std::asin(kappa * lever_arm_x) + noise));
  }
  Segmentation segments;
  segments.segments.push_back({0, times.size(), times.front(), times.back()});
  const LeverArmFit fit = fit_lever_arm_x(offsets, curvature, segments);
  EXPECT_NEAR(fit.lever_arm_x, lever_arm_x, 0.01);
  EXPECT_NEAR(fit.yaw, psi, rad_from_deg(0.002));
  EXPECT_GE(fit.outliers, 12);
  EXPECT_LT(fit.lever_arm_x_std, 0.01);
  EXPECT_NEAR(fit.mean_curvature, 0.0, 1e-3);
}

// On a circle (constant curvature) the yaw and the lever arm cannot be told apart.
TEST(TurnGeometry, ConstantCurvatureLeavesTheLeverArmUnidentified) {
  std::vector<double> times, offsets, curvature;
  for (int i = 0; i < 1000; ++i) {
    times.push_back(0.01 * i);
    curvature.push_back(0.03);
    offsets.push_back(0.02 - std::asin(0.03));
  }
  Segmentation segments;
  segments.segments.push_back({0, times.size(), times.front(), times.back()});
  const LeverArmFit fit = fit_lever_arm_x(offsets, curvature, segments);
  EXPECT_FALSE(std::isfinite(fit.lever_arm_x_std));
  EXPECT_EQ(fit.lever_arm_x, 0.0);
  EXPECT_NEAR(fit.mean_curvature, 0.03, 1e-12);
  // No samples: the zero fit.
  EXPECT_FALSE(std::isfinite(fit_lever_arm_x(offsets, curvature, {}).lever_arm_x_std));
}

TEST(TurnGeometry, OptionsAreChecked) {
  LeverArmFitOptions options;
  options.correlation_s = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car
