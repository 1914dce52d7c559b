#include "x2car/lidar/odometry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "x2car/lidar/lidar_test_support.hpp"
#include "x2car/lidar/odometry_error.hpp"
#include "x2car/lidar/registration.hpp"

namespace x2car::lidar {
namespace {

using ::testing::HasSubstr;
using testing::run_simulated_odometry;
using testing::simulated_lidar_drive;

// ---- constructed scenes ----------------------------------------------------------------------

// Points on the walls, floor and ceiling of a 60 x 40 x 12 m hall around `sensor_in_hall`, with a
// few pillars so that every direction is pinned, seen from the sensor (frame = hall axes, moved).
io::PointCloud hall_sweep(const Eigen::Vector3d& sensor_in_hall, double spacing = 0.5) {
  std::vector<Eigen::Vector3d> points;
  const double x0 = -30, x1 = 30, y0 = -20, y1 = 20, z0 = -2, z1 = 10;
  for (double a = x0; a <= x1; a += spacing) {
    for (double b = y0; b <= y1; b += spacing) {
      points.emplace_back(a, b, z0);
      points.emplace_back(a, b, z1);
    }
    for (double c = z0; c <= z1; c += spacing) {
      points.emplace_back(a, y0, c);
      points.emplace_back(a, y1, c);
    }
  }
  for (double b = y0; b <= y1; b += spacing) {
    for (double c = z0; c <= z1; c += spacing) {
      points.emplace_back(x0, b, c);
      points.emplace_back(x1, b, c);
    }
  }
  for (const Eigen::Vector2d& pillar : {Eigen::Vector2d(10, 8), Eigen::Vector2d(-12, -6)}) {
    for (double angle = 0; angle < 2 * kPi; angle += 0.2) {
      for (double c = z0; c <= z1; c += spacing) {
        points.emplace_back(pillar.x() + 0.5 * std::cos(angle), pillar.y() + 0.5 * std::sin(angle),
                            c);
      }
    }
  }
  io::PointCloud cloud;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d q = p - sensor_in_hall;
    cloud.points.push_back(io::LidarPoint{static_cast<float>(q.x()), static_cast<float>(q.y()),
                                          static_cast<float>(q.z()), 0.0f, 0, 0.0f});
  }
  return cloud;
}

// A flat floor 1.8 m below the sensor, nothing else.
io::PointCloud floor_sweep() {
  io::PointCloud cloud;
  for (float x = -40; x <= 40; x += 0.4f) {
    for (float y = -40; y <= 40; y += 0.4f) cloud.points.push_back({x, y, -1.8f, 0.0f, 0, 0.0f});
  }
  return cloud;
}

// ---- options ---------------------------------------------------------------------------------

TEST(OdometryOptions, DefaultsPassAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(OdometryOptions{}.Check());
  OdometryOptions options;
  options.voxel_size_m = 0.0;
  EXPECT_THAT([&] { options.Check(); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("voxel_size_m")));
  options = {};
  options.min_range_m = 200.0;
  EXPECT_THAT([&] { LidarOdometry odometry(options); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("min_range_m")));
  EXPECT_EQ(to_string(RegistrationStatus::kDegenerate), "degenerate");
  EXPECT_EQ(to_string(RegistrationStatus::kOk), "ok");
}

// The nested knots were hidden from Check() (issue 11): a bad planarity test or ICP setting now
// names its struct and field instead of silently weighting every point.
TEST(OdometryOptions, NestedPlanarityAndIcpSettingsAreChecked) {
  OdometryOptions options;
  options.planarity.max_flatness = -0.1f;
  EXPECT_THAT([&] { options.Check(); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  HasSubstr("PlanarityOptions.max_flatness must be in [0, 1] (got -0.1)")));
  options = {};
  options.planarity.min_points = 2;
  EXPECT_THAT([&] { LidarOdometry odometry(options); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("min_points")));
  EXPECT_NO_THROW(IcpSettings{}.Check());
  IcpSettings settings;
  settings.kernel_scale = 0.0;
  EXPECT_THAT([&] { settings.Check(); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  HasSubstr("IcpSettings.kernel_scale must be > 0 and finite (got 0)")));
  settings = {};
  settings.max_iterations = 0;
  const VoxelHashMap map(1.0f, 20);
  EXPECT_THROW(align_to_map({}, {}, map, Eigen::Isometry3d::Identity(), settings, {}),
               std::invalid_argument);
}

// ---- failure is reported, not hidden ---------------------------------------------------------

TEST(LidarOdometry, RecoversAKnownShiftInAHall) {
  LidarOdometry odometry;
  EXPECT_EQ(odometry.register_sweep(hall_sweep({0, 0, 0}), 0.0).status,
            RegistrationStatus::kFirstSweep);
  const OdometryStep step = odometry.register_sweep(hall_sweep({0.6, -0.3, 0.05}), 0.1);
  EXPECT_EQ(step.status, RegistrationStatus::kOk) << to_string(step.status);
  EXPECT_LT((step.world_from_lidar.translation() - Eigen::Vector3d(0.6, -0.3, 0.05)).norm(), 0.02);
  EXPECT_LT(Eigen::AngleAxisd(step.world_from_lidar.linear()).angle(), rad_from_deg(0.1));
  EXPECT_GT(step.translation_constraint, 0.01);
}

TEST(LidarOdometry, NonFinitePointsAreSkippedAndCounted) {
  io::PointCloud sweep = hall_sweep({0, 0, 0});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  sweep.points.push_back({nan, nan, nan, 0.0f, 0, 0.0f});
  sweep.points.push_back({1.0f, inf, 0.0f, 0.0f, 0, 0.0f});
  sweep.points.push_back({-inf, 2.0f, nan, 0.0f, 0, 0.0f});
  LidarOdometry odometry;
  EXPECT_EQ(odometry.register_sweep(sweep, 0.0).invalid_points, 3u);
  const OdometryStep step = odometry.register_sweep(sweep, 0.1);
  EXPECT_EQ(step.invalid_points, 3u);
  EXPECT_EQ(step.status, RegistrationStatus::kOk);
  EXPECT_TRUE(step.world_from_lidar.matrix().allFinite());
}

// A NaN per-point time used to deskew its point to NaN and put it into the map; times spanning
// far more than a sweep (another unit) would throw the points far away when deskewed.
TEST(LidarOdometry, BrokenPointTimesAreSkippedOrNotTrusted) {
  LidarOdometry odometry;
  for (int k = 0; k < 4; ++k) {
    io::PointCloud sweep = hall_sweep({0.5 * k, 0, 0});
    sweep.has_time = true;
    for (std::size_t i = 0; i < sweep.points.size(); ++i) {
      sweep.points[i].t = 0.1f * static_cast<float>(i) / static_cast<float>(sweep.points.size());
    }
    sweep.points[7].t = std::numeric_limits<float>::quiet_NaN();
    if (k == 3) sweep.points[9].t = 1e6f;  // nanoseconds read as seconds, say
    const OdometryStep step = odometry.register_sweep(sweep, 0.1 * k);
    EXPECT_EQ(step.invalid_points, 1u) << k;
    EXPECT_TRUE(step.world_from_lidar.matrix().allFinite()) << k;
    if (k == 2) {
      EXPECT_TRUE(step.deskewed);
    }
    if (k == 3) {
      EXPECT_FALSE(step.deskewed);
      EXPECT_EQ(step.deskew_time_s, 0.0);
      EXPECT_EQ(step.status, RegistrationStatus::kOk) << to_string(step.status);
    }
  }
}

TEST(LidarOdometry, ASinglePlaneIsDegenerateAndKeepsThePrediction) {
  LidarOdometry odometry;
  odometry.register_sweep(floor_sweep(), 0.0);
  const OdometryStep step = odometry.register_sweep(floor_sweep(), 0.1);
  EXPECT_EQ(step.status, RegistrationStatus::kDegenerate) << to_string(step.status);
  EXPECT_LT(step.translation_constraint, 0.001);
  EXPECT_TRUE(step.world_from_lidar.isApprox(Eigen::Isometry3d::Identity()));  // the prediction
}

TEST(LidarOdometry, TooFewPointsAreReportedWithThePrediction) {
  LidarOdometry odometry;
  odometry.register_sweep(hall_sweep({0, 0, 0}), 0.0);
  odometry.register_sweep(hall_sweep({0.5, 0, 0}), 0.1);  // 5 m/s along x
  io::PointCloud few;
  for (int i = 0; i < 20; ++i) few.points.push_back({10.0f + i, 3.0f, 0.0f, 0.0f, 0, 0.0f});
  const OdometryStep step = odometry.register_sweep(few, 0.2);
  EXPECT_EQ(step.status, RegistrationStatus::kTooFewPoints);
  EXPECT_NEAR(step.world_from_lidar.translation().x(), 1.0, 0.03);  // constant velocity
  const OdometryStep empty = odometry.register_sweep(io::PointCloud{}, 0.3);
  EXPECT_EQ(empty.status, RegistrationStatus::kTooFewPoints);
  EXPECT_NEAR(empty.world_from_lidar.translation().x(), 1.5, 0.05);
  EXPECT_THROW(odometry.register_sweep(hall_sweep({0, 0, 0}), 0.1), std::invalid_argument);
}

// ---- simulated drives ------------------------------------------------------------------------

// Every sweep after the first registers, and the drift over the drive stays within `percent`.
void expect_drift_below(const testing::OdometryRun& run, double percent) {
  if (std::getenv("X2CAR_ODOMETRY_DEBUG") != nullptr) {
    for (std::size_t i = 1; i < run.steps.size(); ++i) {
      const auto& s = run.steps[i];
      const Eigen::Isometry3d est = run.estimate[i - 1].inverse() * run.estimate[i];
      const Eigen::Isometry3d tru = run.truth[i - 1].inverse() * run.truth[i];
      std::cout << i << " " << to_string(s.status) << " it " << s.iterations << " used "
                << s.points_used << "/" << s.source_points << " thr " << s.threshold_m << " rms "
                << s.rms_residual_m << " con " << s.translation_constraint << " "
                << s.rotation_constraint << " est " << est.translation().transpose() << " true "
                << tru.translation().transpose() << "\n";
    }
  }
  for (std::size_t i = 1; i < run.steps.size(); ++i) {
    EXPECT_EQ(run.steps[i].status, RegistrationStatus::kOk)
        << "sweep " << i << ": " << to_string(run.steps[i].status);
  }
  DriftOptions options;
  options.lengths_m = {25.0, 50.0, 100.0};
  options.step = 1;
  const Drift drift = relative_drift(run.estimate, run.truth, options);
  ASSERT_GT(drift.segments, 0u) << "path " << drift.path_length_m << " m";
  EXPECT_LT(drift.translation_percent, percent);
  ::testing::Test::RecordProperty("translation_percent", std::to_string(drift.translation_percent));
  std::cout << "drift " << drift.translation_percent << " %, " << drift.rotation_deg_per_100m
            << " deg/100 m over " << drift.path_length_m << " m\n";
}

class OdometryDrift : public ::testing::TestWithParam<int> {};

TEST_P(OdometryDrift, UrbanDriveStaysBelowOnePercent) {
  const auto run =
      run_simulated_odometry(simulated_lidar_drive(sim::Scenario::kUrban, 12.0, GetParam(), 3))
          .front();
  expect_drift_below(run, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Beams, OdometryDrift, ::testing::Values(32, 64, 128));

TEST(OdometryDeskew, HelpsThroughATurn) {
  // 25 s of urban driving: a stop and a 90-degree turn at an intersection (up to 2.6 deg per
  // sweep), where a sweep that is not deskewed is bent by the turn.
  const auto drive = simulated_lidar_drive(sim::Scenario::kUrban, 25.0, 32, 3);
  OdometryOptions no_deskew;
  no_deskew.deskew = false;
  const auto runs = run_simulated_odometry(drive, {OdometryOptions{}, no_deskew});
  const auto& with_deskew = runs[0];
  const auto& without_deskew = runs[1];
  const double turn =
      Eigen::AngleAxisd((with_deskew.truth.front().inverse() * with_deskew.truth.back()).linear())
          .angle();
  ASSERT_GT(deg_from_rad(turn), 80.0);
  EXPECT_TRUE(with_deskew.steps.back().deskewed);
  EXPECT_FALSE(without_deskew.steps.back().deskewed);
  DriftOptions lengths;
  lengths.lengths_m = {25.0, 50.0, 100.0};
  lengths.step = 1;
  const Drift with = relative_drift(with_deskew.estimate, with_deskew.truth, lengths);
  const Drift without = relative_drift(without_deskew.estimate, without_deskew.truth, lengths);
  std::cout << "deskewed " << with.translation_percent << " %, " << with.rotation_deg_per_100m
            << " deg/100 m; not " << without.translation_percent << " %, "
            << without.rotation_deg_per_100m << " deg/100 m\n";
  EXPECT_LT(with.translation_percent, 0.5 * without.translation_percent);
  EXPECT_LT(with.rotation_deg_per_100m, 0.5 * without.rotation_deg_per_100m);
  // Poses refer to the middle of the sweep (t in [0, 0.1) s at 10 Hz).
  EXPECT_NEAR(with_deskew.steps[5].deskew_time_s, 0.05, 0.001);
}

TEST(OdometrySpeed, AStraightDriveRecoversTheSpeed) {
  // The car pulls away from a standstill and cruises at 50-70 km/h. Speeds over 1 s (10 sweeps):
  // single sweeps scatter by ~1 cm along the road, which is the registration's noise, not drift.
  // The first 2 s (pulling away, when the first sweeps lack a velocity to deskew with and the
  // 1-s windows hold centimetre errors) are left out.
  const auto run =
      run_simulated_odometry(simulated_lidar_drive(sim::Scenario::kStraight, 8.0, 32, 2)).front();
  constexpr std::size_t kWindow = 10;
  double worst = 0.0;
  double top_speed = 0.0;
  for (std::size_t i = 1; i < run.steps.size(); ++i) {
    ASSERT_EQ(run.steps[i].status, RegistrationStatus::kOk) << i;
    if (i < 20) continue;
    const double dt = run.steps[i].time - run.steps[i - kWindow].time;
    const auto speed = [&](const std::vector<Eigen::Isometry3d>& poses) {
      return (poses[i].translation() - poses[i - kWindow].translation()).norm() / dt;
    };
    worst = std::max(worst, std::abs(speed(run.estimate) - speed(run.truth)));
    top_speed = std::max(top_speed, speed(run.truth));
  }
  std::cout << "top speed " << top_speed << " m/s, worst error over 1 s " << worst << " m/s\n";
  EXPECT_GT(top_speed, 10.0);
  EXPECT_LT(worst, 0.05);  // [m/s]
}

}  // namespace
}  // namespace x2car::lidar
