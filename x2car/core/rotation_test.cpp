#include "x2car/core/rotation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "x2car/core/test_matchers.hpp"

namespace x2car {
namespace {

using testing::AngleNearDeg;
using testing::RotationNear;

Eigen::Matrix3d rotation_about_x(double angle) {
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle);
  return r;
}
Eigen::Matrix3d rotation_about_y(double angle) {
  Eigen::Matrix3d r;
  r << std::cos(angle), 0, std::sin(angle), 0, 1, 0, -std::sin(angle), 0, std::cos(angle);
  return r;
}
Eigen::Matrix3d rotation_about_z(double angle) {
  Eigen::Matrix3d r;
  r << std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle), 0, 0, 0, 1;
  return r;
}

TEST(EulerAngles, ComposeAsZYXIntrinsic) {
  const EulerAngles angles{0.1, -0.2, 0.3};
  const Eigen::Matrix3d expected =
      rotation_about_z(angles.yaw) * rotation_about_y(angles.pitch) * rotation_about_x(angles.roll);
  EXPECT_TRUE(rotation_from_euler(angles).isApprox(expected, 1e-15));
}

TEST(EulerAngles, RoundTripOnAGrid) {
  // Every combination of roll/yaw over the whole circle and pitch up to 1e-7 deg from gimbal lock.
  const std::vector<double> pitches_deg = {-90 + 1e-7, -89.99, -60,  -3,       0,
                                           0.01,       45,     89.9, 90 - 1e-7};
  int checked = 0;
  for (double roll_deg = -179.0; roll_deg <= 180.0; roll_deg += 17.0) {
    for (const double pitch_deg : pitches_deg) {
      for (double yaw_deg = -180.0 + 1e-9; yaw_deg <= 180.0; yaw_deg += 23.0) {
        const EulerAngles angles{rad_from_deg(roll_deg), rad_from_deg(pitch_deg),
                                 rad_from_deg(yaw_deg)};
        const Eigen::Matrix3d rotation = rotation_from_euler(angles);
        const EulerAngles recovered = euler_from_rotation(rotation);
        // The rotation always comes back; the angles too except within ~1e-6 deg of gimbal lock,
        // where roll and yaw trade against each other and only the rotation is defined.
        EXPECT_THAT(rotation_from_euler(recovered), RotationNear(rotation, 1e-9));
        EXPECT_NEAR(recovered.pitch, angles.pitch, 1e-12);
        if (std::abs(pitch_deg) < 89.99 + 1e-9) {
          EXPECT_THAT(recovered.roll, AngleNearDeg(angles.roll, 1e-9));
          EXPECT_THAT(recovered.yaw, AngleNearDeg(angles.yaw, 1e-9));
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(EulerAngles, GimbalLockKeepsTheRotation) {
  for (const double pitch : {kPi / 2, -kPi / 2}) {
    const EulerAngles angles{0.4, pitch, -1.1};
    const Eigen::Matrix3d rotation = rotation_from_euler(angles);
    const EulerAngles recovered = euler_from_rotation(rotation);
    EXPECT_DOUBLE_EQ(recovered.roll, 0.0);
    EXPECT_NEAR(std::abs(recovered.pitch), kPi / 2, 1e-7);
    EXPECT_THAT(rotation_from_euler(recovered), RotationNear(rotation, 1e-6));
  }
}

// ---- the sign checks of docs/conventions.md ----------------------------------------------

TEST(SignCheck, PositiveYawTurnsTheSensorXAxisLeft) {
  const Eigen::Matrix3d vehicle_from_sensor = rotation_from_euler({0, 0, rad_from_deg(2.0)});
  const Eigen::Vector3d sensor_x_in_vehicle = vehicle_from_sensor.col(0);
  EXPECT_GT(sensor_x_in_vehicle.y(), 0.0);  // y is left
  EXPECT_NEAR(sensor_x_in_vehicle.y(), std::sin(rad_from_deg(2.0)), 1e-15);
  EXPECT_THAT(euler_from_rotation(vehicle_from_sensor).yaw, AngleNearDeg(rad_from_deg(2.0), 1e-12));
}

TEST(SignCheck, PositivePitchTiltsTheSensorXAxisDown) {
  const Eigen::Matrix3d vehicle_from_sensor = rotation_from_euler({0, rad_from_deg(3.0), 0});
  EXPECT_LT(vehicle_from_sensor.col(0).z(), 0.0);
}

TEST(SignCheck, PositiveRollLowersTheSensorRightSide) {
  const Eigen::Matrix3d vehicle_from_sensor = rotation_from_euler({rad_from_deg(3.0), 0, 0});
  EXPECT_GT(vehicle_from_sensor.col(1).z(), 0.0);     // the left axis rises...
  EXPECT_LT((-vehicle_from_sensor.col(1)).z(), 0.0);  // ...so the right side goes down
}

TEST(SignCheck, LidarPitchedDownSeesTheGroundNormalTiltedTowardsMinusX) {
  const double pitch = rad_from_deg(2.5);
  const double roll = rad_from_deg(-1.5);
  const Eigen::Matrix3d vehicle_from_lidar = rotation_from_euler({roll, pitch, rad_from_deg(4.0)});
  const Eigen::Vector3d ground_normal_in_lidar =
      vehicle_from_lidar.transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_LT(ground_normal_in_lidar.x(), 0.0);
  // The ground-plane formulas of the LiDAR method recover both angles exactly.
  EXPECT_NEAR(std::asin(-ground_normal_in_lidar.x()), pitch, 1e-15);
  EXPECT_NEAR(std::atan2(ground_normal_in_lidar.y(), ground_normal_in_lidar.z()), roll, 1e-15);
}

TEST(SignCheck, CameraPitchedDownSeesTheVanishingPointAboveTheImageCentre) {
  Eigen::Matrix3d body_from_optical;  // R_B_O: columns are the optical axes in the body frame
  body_from_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Matrix3d vehicle_from_body = rotation_from_euler({0, rad_from_deg(5.0), 0});
  const Eigen::Matrix3d vehicle_from_optical = vehicle_from_body * body_from_optical;
  const Eigen::Vector3d driving_direction_in_optical =
      vehicle_from_optical.transpose() * Eigen::Vector3d::UnitX();
  ASSERT_GT(driving_direction_in_optical.z(), 0.0);  // in front of the camera
  const double v_minus_cy = driving_direction_in_optical.y() / driving_direction_in_optical.z();
  EXPECT_LT(v_minus_cy, 0.0);  // image y grows downwards: negative = above the centre
}

// ---- other representations ---------------------------------------------------------------

TEST(Rotation, QuaternionAndRotationVectorRoundTrips) {
  const EulerAngles angles{0.3, -0.7, 2.9};
  const Eigen::Matrix3d rotation = rotation_from_euler(angles);
  const EulerAngles from_quaternion = euler_from_quaternion(quaternion_from_euler(angles));
  EXPECT_THAT(rotation_from_euler(from_quaternion), RotationNear(rotation, 1e-10));
  const Eigen::Vector3d rotation_vector = rotation_vector_from_rotation(rotation);
  EXPECT_LE(rotation_vector.norm(), kPi + 1e-12);
  EXPECT_THAT(rotation_from_rotation_vector(rotation_vector), RotationNear(rotation, 1e-10));
  EXPECT_TRUE(rotation_from_rotation_vector(Eigen::Vector3d::Zero()).isIdentity());
}

TEST(Rotation, NearestRotationRepairsASlightlyOffMatrix) {
  const Eigen::Matrix3d rotation = rotation_from_euler({0.1, 0.2, 0.3});
  Eigen::Matrix3d noisy = rotation;
  noisy(0, 1) += 1e-4;
  EXPECT_FALSE(is_rotation(noisy));
  const Eigen::Matrix3d repaired = nearest_rotation(noisy);
  EXPECT_TRUE(is_rotation(repaired, 1e-12));
  EXPECT_THAT(repaired, RotationNear(rotation, 0.01));
  EXPECT_FALSE(is_rotation(-Eigen::Matrix3d::Identity()));  // a reflection
}

TEST(Rotation, AngleBetween) {
  const Eigen::Matrix3d a = rotation_from_euler({0, 0, 0.25});
  EXPECT_NEAR(angle_between(a, Eigen::Matrix3d::Identity()), 0.25, 1e-12);
}

// ---- plain angles ------------------------------------------------------------------------

TEST(WrapAngle, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);
  EXPECT_NEAR(wrap_angle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(2 * kPi + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(wrap_angle(-2 * kPi - 0.1), -0.1, 1e-12);
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  for (double angle = -20.0; angle <= 20.0; angle += 0.37) {
    const double wrapped = wrap_angle(angle);
    EXPECT_GT(wrapped, -kPi);
    EXPECT_LE(wrapped, kPi);
    EXPECT_NEAR(std::remainder(wrapped - angle, 2 * kPi), 0.0, 1e-12);
  }
}

TEST(AngleDifference, TakesTheShortWayAcrossTheSeam) {
  EXPECT_NEAR(angle_difference(rad_from_deg(-179), rad_from_deg(179)), rad_from_deg(2), 1e-12);
  EXPECT_NEAR(angle_difference(rad_from_deg(179), rad_from_deg(-179)), rad_from_deg(-2), 1e-12);
  EXPECT_NEAR(angle_difference(0.3, 0.1), 0.2, 1e-15);
}

TEST(CircularMean, AveragesAcrossTheSeam) {
  const std::vector<double> angles = {rad_from_deg(178), rad_from_deg(-178), rad_from_deg(179),
                                      rad_from_deg(-179)};
  EXPECT_THAT(circular_mean(angles), AngleNearDeg(kPi, 1e-9));
  EXPECT_NEAR(mean_resultant_length(angles), 1.0, 1e-3);
}

TEST(CircularMean, HonoursWeights) {
  const std::vector<double> angles = {rad_from_deg(10), rad_from_deg(20)};
  const std::vector<double> weights = {3.0, 1.0};
  // Unit vectors at 10 and 20 deg weighted 3:1: the mean direction is atan2 of the weighted sums.
  const double expected = std::atan2(3 * std::sin(rad_from_deg(10)) + std::sin(rad_from_deg(20)),
                                     3 * std::cos(rad_from_deg(10)) + std::cos(rad_from_deg(20)));
  EXPECT_NEAR(circular_mean(angles, weights), expected, 1e-15);
  EXPECT_LT(circular_mean(angles, weights), rad_from_deg(15));
}

TEST(CircularMean, RejectsInputWithoutAMean) {
  EXPECT_THROW(circular_mean({}), std::invalid_argument);
  const std::vector<double> opposite = {0.0, kPi};
  EXPECT_THROW(circular_mean(opposite), std::invalid_argument);
  const std::vector<double> angles = {0.1, 0.2};
  const std::vector<double> wrong_size = {1.0};
  EXPECT_THROW(circular_mean(angles, wrong_size), std::invalid_argument);
  const std::vector<double> negative = {1.0, -1.0};
  EXPECT_THROW(circular_mean(angles, negative), std::invalid_argument);
}

// The end of the angles' axis most of them lie on: ahead for a course mostly driven forward, with
// some backing up at the other end, at any offset (a device mounted backwards: about pi).
TEST(MajorityAxisEnd, IsTheEndMostAnglesLieOn) {
  const std::vector<double> mostly_ahead = {0.02, -0.01, 0.0, kPi - 0.01, 0.01};
  EXPECT_NEAR(*majority_axis_end(mostly_ahead, 0.5), 0.002, 1e-4);
  std::vector<double> turned;
  for (const double angle : mostly_ahead) turned.push_back(wrap_angle(angle + kPi));
  EXPECT_NEAR(std::abs(*majority_axis_end(turned, 0.5)), kPi - 0.002, 1e-4);
  const std::vector<double> sideways = {kPi / 2, kPi / 2 + 0.02, -kPi / 2, kPi / 2 - 0.02};
  EXPECT_NEAR(*majority_axis_end(sideways, 0.5), kPi / 2, 1e-3);
  EXPECT_FALSE(majority_axis_end({}, 0.5));
  const std::vector<double> across = {0.0, kPi / 2};  // doubled: opposite, no axis
  EXPECT_FALSE(majority_axis_end(across, 0.0));
  const std::vector<double> spread = {0.0, kPi / 4};  // doubled: 90 deg apart, length 0.71
  EXPECT_TRUE(majority_axis_end(spread, 0.7));
  EXPECT_FALSE(majority_axis_end(spread, 0.75));
}

TEST(Azimuth, ConvertsToEnuHeading) {
  EXPECT_NEAR(heading_enu_from_azimuth(0.0), kPi / 2, 1e-15);   // north
  EXPECT_NEAR(heading_enu_from_azimuth(kPi / 2), 0.0, 1e-15);   // east
  EXPECT_NEAR(heading_enu_from_azimuth(kPi), -kPi / 2, 1e-15);  // south
  EXPECT_NEAR(heading_enu_from_azimuth(-kPi / 2), kPi, 1e-15);  // west
  EXPECT_NEAR(azimuth_from_heading_enu(heading_enu_from_azimuth(0.7)), 0.7, 1e-15);
}

}  // namespace
}  // namespace x2car
