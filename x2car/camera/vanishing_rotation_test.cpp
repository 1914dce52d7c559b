#include "x2car/camera/vanishing_rotation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "x2car/core/camera_model.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::camera {
namespace {

using x2car::testing::RotationNear;

Eigen::Matrix3d kitti_camera_matrix() { return core::camera_preset("kitti").camera_matrix(); }

VanishingGeometry geometry_of(const EulerAngles& angles) {
  const std::optional<VanishingGeometry> geometry =
      vanishing_geometry_from_rotation(rotation_from_euler(angles), kitti_camera_matrix());
  EXPECT_TRUE(geometry.has_value());
  return geometry.value_or(VanishingGeometry{});
}

// DESIGN §1 sign checks, each both ways.
TEST(VanishingRotation, PitchedDownSeesTheVanishingPointAboveTheCentre) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const VanishingGeometry down = geometry_of({0.0, rad_from_deg(3.0), 0.0});
  EXPECT_LT(down.vanishing_point_px.y(), intrinsics.cy - 30.0);
  EXPECT_NEAR(down.vanishing_point_px.x(), intrinsics.cx, 1e-9);
  const VanishingGeometry up = geometry_of({0.0, rad_from_deg(-3.0), 0.0});
  EXPECT_GT(up.vanishing_point_px.y(), intrinsics.cy + 30.0);
  // The exact offset: fy tan(pitch).
  EXPECT_NEAR(intrinsics.cy - down.vanishing_point_px.y(),
              intrinsics.fy * std::tan(rad_from_deg(3.0)), 1e-9);
  const std::optional<EulerAngles> angles = vehicle_from_camera_angles(
      down.vanishing_point_px, down.horizon_line, intrinsics.camera_matrix());
  ASSERT_TRUE(angles.has_value());
  EXPECT_NEAR(angles->pitch, rad_from_deg(3.0), 1e-12);
}

TEST(VanishingRotation, YawedLeftSeesTheVanishingPointRightOfTheCentre) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const VanishingGeometry left = geometry_of({0.0, 0.0, rad_from_deg(2.0)});
  EXPECT_NEAR(left.vanishing_point_px.x() - intrinsics.cx,
              intrinsics.fx * std::tan(rad_from_deg(2.0)), 1e-9);
  EXPECT_NEAR(left.vanishing_point_px.y(), intrinsics.cy, 1e-9);
  const VanishingGeometry right = geometry_of({0.0, 0.0, rad_from_deg(-2.0)});
  EXPECT_LT(right.vanishing_point_px.x(), intrinsics.cx - 20.0);
  const std::optional<EulerAngles> angles = vehicle_from_camera_angles(
      left.vanishing_point_px, left.horizon_line, intrinsics.camera_matrix());
  ASSERT_TRUE(angles.has_value());
  EXPECT_NEAR(angles->yaw, rad_from_deg(2.0), 1e-12);
}

TEST(VanishingRotation, RolledLeftSideUpSeesTheHorizonRiseToTheRight) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const VanishingGeometry rolled = geometry_of({rad_from_deg(2.5), 0.0, 0.0});
  // The horizon at the image's right edge is higher (smaller v) than at its left edge.
  const auto v_at = [](const Eigen::Vector3d& line, double u) {
    return -(line.x() * u + line.z()) / line.y();
  };
  EXPECT_LT(v_at(rolled.horizon_line, 1241.0), v_at(rolled.horizon_line, 0.0) - 10.0);
  // For a level camera (no pitch or yaw) the horizon's angle is exactly the roll.
  EXPECT_NEAR(horizon_angle(rolled.horizon_line), rad_from_deg(2.5), 1e-12);
  const VanishingGeometry other_way = geometry_of({rad_from_deg(-2.5), 0.0, 0.0});
  EXPECT_GT(v_at(other_way.horizon_line, 1241.0), v_at(other_way.horizon_line, 0.0) + 10.0);
  EXPECT_NEAR(horizon_angle(other_way.horizon_line), rad_from_deg(-2.5), 1e-12);
  // The vanishing point of a rolled camera stays at the principal point.
  EXPECT_NEAR((rolled.vanishing_point_px - Eigen::Vector2d(intrinsics.cx, intrinsics.cy)).norm(),
              0.0, 1e-9);
  const std::optional<EulerAngles> angles = vehicle_from_camera_angles(
      other_way.vanishing_point_px, other_way.horizon_line, intrinsics.camera_matrix());
  ASSERT_TRUE(angles.has_value());
  EXPECT_NEAR(angles->roll, rad_from_deg(-2.5), 1e-12);
}

TEST(VanishingRotation, TheVanishingPointLiesOnTheHorizon) {
  const VanishingGeometry geometry =
      geometry_of({rad_from_deg(1.0), rad_from_deg(-4.0), rad_from_deg(6.0)});
  EXPECT_NEAR(geometry.horizon_line.dot(geometry.vanishing_point_px.homogeneous()), 0.0, 1e-9);
  EXPECT_NEAR(geometry.horizon_line.head<2>().norm(), 1.0, 1e-12);
}

// Exact synthetic data: every rotation within +-10 deg comes back to 1e-9 deg, on a camera
// with a principal point off centre and fx != fy.
TEST(VanishingRotation, RecoversRandomRotationsExactly) {
  Eigen::Matrix3d camera_matrix;
  camera_matrix << 1000.0, 0.0, 650.0, 0.0, 980.0, 330.0, 0.0, 0.0, 1.0;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> angle(-rad_from_deg(10.0), rad_from_deg(10.0));
  for (int i = 0; i < 500; ++i) {
    const EulerAngles truth{angle(random), angle(random), angle(random)};
    const Eigen::Matrix3d rotation = rotation_from_euler(truth);
    const std::optional<VanishingGeometry> geometry =
        vanishing_geometry_from_rotation(rotation, camera_matrix);
    ASSERT_TRUE(geometry.has_value());
    const std::optional<Eigen::Matrix3d> recovered = vehicle_from_camera_rotation(
        geometry->vanishing_point_px, geometry->horizon_line, camera_matrix);
    ASSERT_TRUE(recovered.has_value());
    EXPECT_THAT(*recovered, RotationNear(rotation, 1e-9));
    const EulerAngles angles = euler_from_rotation(*recovered);
    EXPECT_NEAR(angles.roll, truth.roll, 1e-11);
    EXPECT_NEAR(angles.pitch, truth.pitch, 1e-11);
    EXPECT_NEAR(angles.yaw, truth.yaw, 1e-11);
  }
}

// A horizon that does not pass through the vanishing point (noisy estimates) changes only the
// roll: pitch and yaw are the vanishing point's.
TEST(VanishingRotation, TheHorizonOnlySetsTheRoll) {
  const Eigen::Matrix3d camera_matrix = kitti_camera_matrix();
  const EulerAngles truth{rad_from_deg(1.0), rad_from_deg(2.0), rad_from_deg(-3.0)};
  VanishingGeometry geometry = geometry_of(truth);
  geometry.horizon_line.z() += 15.0;  // shifted 15 px down
  const std::optional<EulerAngles> angles =
      vehicle_from_camera_angles(geometry.vanishing_point_px, geometry.horizon_line, camera_matrix);
  ASSERT_TRUE(angles.has_value());
  const std::optional<EulerAngles> exact = vehicle_from_camera_angles(
      geometry_of(truth).vanishing_point_px, geometry_of(truth).horizon_line, camera_matrix);
  ASSERT_TRUE(exact.has_value());
  // Same forward axis: R_V_B's first row is the car's x axis seen from B, unchanged.
  const Eigen::Matrix3d shifted = rotation_from_euler(*angles);
  const Eigen::Matrix3d reference = rotation_from_euler(*exact);
  EXPECT_LT((shifted.row(0) - reference.row(0)).norm(), 1e-12);
}

TEST(VanishingRotation, DegenerateInputGivesNothing) {
  const Eigen::Matrix3d camera_matrix = kitti_camera_matrix();
  const Eigen::Vector2d centre(609.5593, 172.854);
  EXPECT_FALSE(vehicle_from_camera_rotation(centre, Eigen::Vector3d::Zero(), camera_matrix));
  EXPECT_FALSE(vehicle_from_camera_rotation(Eigen::Vector2d(NAN, 0.0), Eigen::Vector3d(0, 1, -170),
                                            camera_matrix));
  // A horizon at infinity: its plane's normal is the optical axis, the forward ray itself.
  EXPECT_FALSE(vehicle_from_camera_rotation(centre, Eigen::Vector3d(0.0, 0.0, 1.0), camera_matrix));
  EXPECT_FALSE(optical_from_vehicle(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -2)));
  EXPECT_FALSE(horizon_from_up(Eigen::Vector3d(0, 0, 1), camera_matrix));
  // Forward pointing behind the camera has no vanishing point in the image.
  EXPECT_FALSE(
      vanishing_geometry_from_rotation(rotation_from_euler({0.0, 0.0, kPi}), camera_matrix));
}

}  // namespace
}  // namespace x2car::camera
