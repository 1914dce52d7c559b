#include "x2car/lidar/ground.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "x2car/core/test_matchers.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::lidar {
namespace {

using x2car::testing::AngleNearDeg;

// ---- constructed sweeps ----------------------------------------------------------------------

io::LidarPoint lidar_point(const Eigen::Vector3d& p_in_lidar) {
  io::LidarPoint point;
  point.x = static_cast<float>(p_in_lidar.x());
  point.y = static_cast<float>(p_in_lidar.y());
  point.z = static_cast<float>(p_in_lidar.z());
  return point;
}

// A LiDAR at vehicle_from_lidar above the flat road z = 0 of V: 32 beams from -25 to -2 deg, a
// column every 0.5 deg, range noise `noise_m` [m] (1 sigma). With `clutter`, also walls 6 m to
// both sides, a car ahead on the left and a low hedge behind: points that are not road.
io::PointCloud flat_road_sweep(const Eigen::Isometry3d& vehicle_from_lidar, double noise_m,
                               bool clutter, std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  io::PointCloud cloud;
  const Eigen::Matrix3d& rotation = vehicle_from_lidar.linear();
  const Eigen::Vector3d origin = vehicle_from_lidar.translation();
  for (int column = 0; column < 720; ++column) {
    const double azimuth = rad_from_deg(0.5 * column);
    for (int beam = 0; beam < 32; ++beam) {
      const double elevation = rad_from_deg(-25.0 + 23.0 * beam / 31.0);
      const Eigen::Vector3d ray_in_lidar(std::cos(elevation) * std::cos(azimuth),
                                         std::cos(elevation) * std::sin(azimuth),
                                         std::sin(elevation));
      const Eigen::Vector3d ray = rotation * ray_in_lidar;
      if (ray.z() >= 0.0) continue;
      const double range = -origin.z() / ray.z();
      if (range > 80.0) continue;
      cloud.points.push_back(lidar_point(ray_in_lidar * (range + noise(rng))));
    }
  }
  if (clutter) {
    const Eigen::Isometry3d lidar_from_vehicle = vehicle_from_lidar.inverse();
    const auto add = [&](const Eigen::Vector3d& p_in_vehicle) {
      cloud.points.push_back(lidar_point(lidar_from_vehicle * p_in_vehicle));
    };
    for (double x = -30.0; x <= 30.0; x += 0.1) {
      for (double z = 0.0; z <= 4.0; z += 0.2) {
        add({x, 6.0, z});  // walls
        add({x, -6.0, z});
      }
    }
    for (double x = 8.0; x <= 12.5; x += 0.05) {  // a car: its side and its rear
      for (double z = 0.2; z <= 1.5; z += 0.05) add({x, 1.5, z});
    }
    for (double y = 1.5; y <= 3.3; y += 0.05) {
      for (double z = 0.2; z <= 1.5; z += 0.05) add({8.0, y, z});
    }
    for (double y = -3.0; y <= 3.0; y += 0.05) {  // a hedge 0.4 m high behind the car
      for (double z = 0.0; z <= 0.4; z += 0.05) add({-9.0, y, z});
    }
  }
  return cloud;
}

Eigen::Isometry3d mounting(double roll_deg, double pitch_deg, double yaw_deg, double height_m) {
  return make_transform(
      EulerAngles{rad_from_deg(roll_deg), rad_from_deg(pitch_deg), rad_from_deg(yaw_deg)},
      Eigen::Vector3d(1.3, 0.1, height_m));
}

GroundPlane fitted_plane(const io::PointCloud& cloud, std::uint64_t seed = 1) {
  const GroundFit fit = fit_ground(cloud, GroundOptions{}, seed);
  EXPECT_TRUE(fit.plane.has_value()) << fit.failure;
  return fit.plane.value_or(GroundPlane{});
}

// ---- the angles from a normal ----------------------------------------------------------------

TEST(GroundAngles, AreTheRollAndPitchOfTheMountingForAnyYaw) {
  for (const double yaw_deg : {-170.0, -5.0, 0.0, 30.0, 120.0}) {
    const EulerAngles angles{rad_from_deg(4.0), rad_from_deg(-7.0), rad_from_deg(yaw_deg)};
    // The road's normal (V's z axis) in LiDAR coordinates: R_V_L^T e_z.
    const Eigen::Vector3d normal = rotation_from_euler(angles).transpose().col(2);
    EXPECT_THAT(roll_from_ground(normal), AngleNearDeg(angles.roll, 1e-9));
    EXPECT_THAT(pitch_from_ground(normal), AngleNearDeg(angles.pitch, 1e-9));
  }
}

TEST(GroundAngles, APitchedDownLidarSeesTheNormalTiltedTowardsMinusX) {
  const Eigen::Vector3d normal =
      rotation_from_euler({0.0, rad_from_deg(3.0), 0.0}).transpose().col(2);
  EXPECT_LT(normal.x(), 0.0);
  EXPECT_GT(pitch_from_ground(normal), 0.0);
}

// ---- fits on constructed sweeps --------------------------------------------------------------

TEST(FitGround, LevelLidarSeesANormalAlongZAndItsMountingHeight) {
  const GroundPlane plane = fitted_plane(flat_road_sweep(mounting(0, 0, 0, 1.8), 0.0, false));
  EXPECT_NEAR(plane.normal_in_lidar.z(), 1.0, 1e-9);
  EXPECT_NEAR(plane.height_m, 1.8, 1e-5);
  EXPECT_LT(plane.rms_m, 1e-5);
}

TEST(FitGround, LidarPitchedDownReportsPositivePitchAndNormalTowardsMinusX) {
  const GroundPlane plane = fitted_plane(flat_road_sweep(mounting(0, 2.0, 0, 1.8), 0.0, false));
  EXPECT_LT(plane.normal_in_lidar.x(), -0.03);
  EXPECT_THAT(pitch_from_ground(plane.normal_in_lidar), AngleNearDeg(rad_from_deg(2.0), 1e-4));
  EXPECT_THAT(roll_from_ground(plane.normal_in_lidar), AngleNearDeg(0.0, 1e-4));
  EXPECT_NEAR(plane.height_m, 1.8, 1e-5);
}

TEST(FitGround, LidarRolledReportsItsRoll) {
  const GroundPlane plane = fitted_plane(flat_road_sweep(mounting(2.5, 0, 0, 1.6), 0.0, false));
  EXPECT_GT(plane.normal_in_lidar.y(), 0.03);  // roll > 0 lowers the right side: +y sees it rise
  EXPECT_THAT(roll_from_ground(plane.normal_in_lidar), AngleNearDeg(rad_from_deg(2.5), 1e-4));
  EXPECT_THAT(pitch_from_ground(plane.normal_in_lidar), AngleNearDeg(0.0, 1e-4));
}

TEST(FitGround, RecoversATiltedYawedMountingAmongWallsCarsAndNoise) {
  const Eigen::Isometry3d vehicle_from_lidar = mounting(-1.7, 2.9, 4.0, 1.95);
  const GroundPlane plane = fitted_plane(flat_road_sweep(vehicle_from_lidar, 0.02, true));
  const EulerAngles truth = euler_from_rotation(vehicle_from_lidar.linear());
  EXPECT_THAT(roll_from_ground(plane.normal_in_lidar), AngleNearDeg(truth.roll, 0.01));
  EXPECT_THAT(pitch_from_ground(plane.normal_in_lidar), AngleNearDeg(truth.pitch, 0.01));
  EXPECT_NEAR(plane.height_m, 1.95, 0.003);
  // Range noise along oblique rays is mostly parallel to the road: less than 0.02 m across it.
  EXPECT_GT(plane.rms_m, 0.002);
  EXPECT_LT(plane.rms_m, 0.02);
  EXPECT_GT(plane.inliers, 1000u);
}

TEST(FitGround, IsDeterministicForASeed) {
  const io::PointCloud cloud = flat_road_sweep(mounting(1.0, -1.0, 0, 1.7), 0.03, true);
  const GroundFit a = fit_ground(cloud, GroundOptions{}, 42);
  const GroundFit b = fit_ground(cloud, GroundOptions{}, 42);
  ASSERT_TRUE(a.plane && b.plane);
  EXPECT_EQ(a.plane->normal_in_lidar, b.plane->normal_in_lidar);
  EXPECT_EQ(a.plane->height_m, b.plane->height_m);
  EXPECT_EQ(a.plane->inliers, b.plane->inliers);
  // Another seed draws other samples but finds the same road.
  const GroundFit c = fit_ground(cloud, GroundOptions{}, 43);
  ASSERT_TRUE(c.plane);
  EXPECT_LT(std::acos(std::min(1.0, c.plane->normal_in_lidar.dot(a.plane->normal_in_lidar))),
            rad_from_deg(0.005));
}

TEST(FitGround, SkipsAndCountsNanAndInfPoints) {
  io::PointCloud cloud = flat_road_sweep(mounting(0.5, 1.5, 0, 1.8), 0.0, false);
  const GroundPlane clean = fitted_plane(cloud);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 100; ++i) {
    io::LidarPoint bad;
    bad.x = i % 3 == 0 ? nan : 5.0f;
    bad.y = i % 3 == 1 ? inf : 0.0f;
    bad.z = i % 3 == 2 ? -inf : -1.8f;
    cloud.points.insert(cloud.points.begin() + 10 * i, bad);
  }
  const GroundFit fit = fit_ground(cloud, GroundOptions{}, 1);
  ASSERT_TRUE(fit.plane) << fit.failure;
  EXPECT_EQ(fit.invalid_points, 100u);
  EXPECT_TRUE(std::isfinite(fit.plane->height_m));
  EXPECT_LT((fit.plane->normal_in_lidar - clean.normal_in_lidar).norm(), 1e-9);
}

TEST(FitGround, TooFewPointsGiveAFailureWithAReason) {
  io::PointCloud cloud;
  EXPECT_THAT(fit_ground(cloud, GroundOptions{}, 1).failure, ::testing::HasSubstr("only 0 of 0"));
  cloud = flat_road_sweep(mounting(0, 0, 0, 1.8), 0.0, false);
  cloud.points.resize(50);
  const GroundFit fit = fit_ground(cloud, GroundOptions{}, 1);
  EXPECT_FALSE(fit.plane);
  EXPECT_THAT(fit.failure, ::testing::HasSubstr("need 300"));
  // Only a wall, no road: no plane within the tilt limit.
  io::PointCloud wall;
  for (double x = -20.0; x <= 20.0; x += 0.05) {
    for (double z = -1.8; z <= 3.0; z += 0.1) wall.points.push_back(lidar_point({x, 3.5, z}));
  }
  const GroundFit no_road = fit_ground(wall, GroundOptions{}, 1);
  EXPECT_FALSE(no_road.plane);
  EXPECT_FALSE(no_road.failure.empty());
}

TEST(GroundOptions, CheckNamesTheBadField) {
  GroundOptions options;
  options.max_range_m = 1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = GroundOptions{};
  options.max_tilt = 2.0;
  EXPECT_THROW(
      {
        try {
          options.Check();
        } catch (const std::invalid_argument& error) {
          EXPECT_THAT(error.what(), ::testing::HasSubstr("max_tilt"));
          throw;
        }
      },
      std::invalid_argument);
}

// ---- the simulator's flat straight drive -----------------------------------------------------

// A flat, level straight road with the full urban scenery (buildings, parked and moving cars),
// the body held level on its suspension so that the road plane is V's xy plane at every instant.
TEST(FitGround, OnASimulatedFlatDriveReportsTheMountingRollPitchAndHeight) {
  sim::SimulationOptions options =
      sim::testing::simulated_lidar_drive(sim::Scenario::kStraight, 2.0, 32, 3);
  options.route.vertical.max_grade = 0.0;
  options.route.vertical.max_crossfall = 0.0;
  options.motion.roll_gain = 0.0;
  options.motion.pitch_gain = 0.0;
  io::SensorMounting mount;
  mount.translation = {1.4, -0.1, 1.85};
  mount.rotation = {rad_from_deg(1.2), rad_from_deg(2.4), rad_from_deg(-3.0)};
  options.mountings["lidar"] = mount;
  const sim::Simulation simulation = sim::simulate(options);
  const sim::WorldScene scene(simulation.world);
  const sim::LidarSimulator lidar(scene, simulation.states, mount.vehicle_from_sensor(),
                                  simulation.lidar->options, simulation.lidar->seed);
  for (const std::size_t index : {std::size_t{2}, std::size_t{15}}) {
    const GroundFit fit = fit_ground(lidar.sweep(index).cloud, GroundOptions{}, index);
    ASSERT_TRUE(fit.plane) << fit.failure;
    EXPECT_THAT(roll_from_ground(fit.plane->normal_in_lidar),
                AngleNearDeg(mount.rotation.roll, 0.02));
    EXPECT_THAT(pitch_from_ground(fit.plane->normal_in_lidar),
                AngleNearDeg(mount.rotation.pitch, 0.02));
    EXPECT_NEAR(fit.plane->height_m, 1.85, 0.005);
  }
}

}  // namespace
}  // namespace x2car::lidar
