#include "x2car/lidar/se3.hpp"

#include <gtest/gtest.h>

#include "x2car/core/rotation.hpp"

namespace x2car::lidar {
namespace {

TEST(Se3, ExpAndLogAreInverseAndScrewMotionMatchesExp) {
  Vector6d twist;
  twist << 1.3, -0.4, 0.2, 0.05, -0.3, 0.9;
  const Eigen::Isometry3d pose = se3_exp(twist);
  EXPECT_TRUE(se3_log(pose).isApprox(twist, 1e-12));
  // A screw: quarter turn about z while moving along x ends on the arc, not the chord.
  Vector6d quarter;
  quarter << kPi / 2, 0, 0, 0, 0, kPi / 2;
  EXPECT_TRUE(se3_exp(quarter).translation().isApprox(Eigen::Vector3d(1, 1, 0), 1e-12));
  const ScrewMotion motion(twist);
  const Eigen::Vector3f point(20.0f, -5.0f, 1.0f);
  for (const float tau : {-0.05f, 0.0f, 0.03f, 0.6f}) {
    const Eigen::Vector3d expected = se3_exp(twist * tau) * point.cast<double>();
    EXPECT_LT((motion.apply(point, tau).cast<double>() - expected).norm(), 1e-4) << tau;
  }
}

}  // namespace
}  // namespace x2car::lidar
