#include "x2car/sim/lidar_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "x2car/core/test_matchers.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/vehicle_motion.hpp"

namespace x2car::sim {
namespace {

using x2car::testing::AngleNearDeg;

// ---- scenes made for the tests ---------------------------------------------------------------

// A flat straight road along +x from the ENU origin.
Route flat_straight_route(double length_m) {
  RoadPlan plan;
  plan.curvature = {{0.0, 0.0}, {length_m, 0.0}};
  return Route(plan, VerticalProfile{});
}

// Only a flat road plane, 120 m wide, along the route.
World flat_world(const Route& route) {
  World world;
  Random random(1);
  world.road = build_road_layout(route, Scenario::kUrban, RoadOptions{}, random);
  WorldObject road;
  road.kind = ObjectKind::kRoad;
  road.material = standard_material(Surface::kAsphalt);
  road.strip = RoadStrip{world.road.s_begin(), world.road.s_end(), -60.0, 60.0, 0.0, 0.0};
  world.objects.push_back(road);
  return world;
}

// The car on the route's line (y = 0, z = 0) facing +x, from x0 at a constant speed, at 100 Hz.
VehicleStates straight_states(double x0_m, double speed_mps, double duration_s) {
  VehicleStates states;
  for (int k = 0; k <= static_cast<int>(std::lround(duration_s * 100.0)); ++k) {
    VehicleState state;
    state.time = k / 100.0;
    state.world_from_vehicle.translation() = Eigen::Vector3d(x0_m + speed_mps * state.time, 0, 0);
    state.speed = speed_mps;
    state.arc_length = x0_m + speed_mps * state.time;
    states.push_back(state);
  }
  return states;
}

LidarOptions test_options(double azimuth_step_deg = 1.0) {
  LidarOptions options;
  options.azimuth_step = rad_from_deg(azimuth_step_deg);
  options.dropout_probability = 0.0;
  return options;
}

Eigen::Isometry3d mounting(double height_m, const EulerAngles& angles = {}) {
  return make_transform(angles, Eigen::Vector3d(1.2, 0.0, height_m));
}

// ---- a drive with grade and crossfall --------------------------------------------------------

struct UrbanDrive {
  Route route;
  VehicleStates states;
  World world;
  Eigen::Isometry3d vehicle_from_lidar;
};

UrbanDrive urban_drive(std::uint64_t seed, double duration_s) {
  const VehicleMotionOptions motion;
  Route route = generate_route(Scenario::kUrban,
                               route_length_for(Scenario::kUrban, duration_s, motion), seed);
  VehicleStates states = simulate_vehicle_motion(route, Scenario::kUrban, duration_s, motion, seed);
  World world = generate_world(route, Scenario::kUrban, states, {}, seed);
  Random random(seed);
  const Eigen::Isometry3d vehicle_from_lidar = draw_mounting("lidar", random).vehicle_from_sensor();
  return {std::move(route), std::move(states), std::move(world), vehicle_from_lidar};
}

// Height of a world point above the route's road surface [m]: the point is projected onto the
// route's plan near s_guess (within [s_low, s_high]), then compared with z(s) + crossfall(s) *
// lateral (route.hpp).
double height_above_road(const Route& route, const Eigen::Vector3d& point, double s_guess,
                         double s_low, double s_high) {
  s_low = std::max(s_low, 0.0);
  s_high = std::min(s_high, route.length());
  double s = std::clamp(s_guess, s_low, s_high);
  RoutePoint p = route.at(s);
  for (int iteration = 0; iteration < 5; ++iteration) {
    const Eigen::Vector2d tangent(std::cos(p.heading_enu), std::sin(p.heading_enu));
    const Eigen::Vector2d offset = point.head<2>() - Eigen::Vector2d(p.x, p.y);
    const double lateral = offset.dot(Eigen::Vector2d(-tangent.y(), tangent.x()));
    s = std::clamp(s + offset.dot(tangent) / (1.0 - p.curvature * lateral), s_low, s_high);
    p = route.at(s);
  }
  // Beyond the route's ends the road continues straight at the end's grade (road_layout.hpp).
  const Eigen::Vector2d tangent(std::cos(p.heading_enu), std::sin(p.heading_enu));
  const Eigen::Vector2d offset = point.head<2>() - Eigen::Vector2d(p.x, p.y);
  const double lateral = offset.dot(Eigen::Vector2d(-tangent.y(), tangent.x()));
  return point.z() - (p.z + p.grade * offset.dot(tangent) + p.crossfall * lateral);
}

// The unit normal (z > 0) of the plane through points, and its distance from the origin.
std::pair<Eigen::Vector3d, double> fit_plane(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::MatrixXd centred(points.size(), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    centred.row(static_cast<Eigen::Index>(i)) = (points[i] - mean).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  Eigen::Vector3d normal = svd.matrixV().col(2);
  if (normal.z() < 0.0) normal = -normal;
  return {normal, -normal.dot(mean)};
}

Eigen::Vector3d position(const io::LidarPoint& p) { return {p.x, p.y, p.z}; }

bool same_points(const io::PointCloud& a, const io::PointCloud& b) {
  return std::equal(a.points.begin(), a.points.end(), b.points.begin(), b.points.end(),
                    [](const io::LidarPoint& p, const io::LidarPoint& q) {
                      return p.x == q.x && p.y == q.y && p.z == q.z && p.intensity == q.intensity &&
                             p.ring == q.ring && p.t == q.t;
                    });
}

// ---- tests -----------------------------------------------------------------------------------

TEST(LidarBeams, TablesHaveTheirCountsAndElevationRanges) {
  struct Expected {
    int beams;
    double low_deg, high_deg;
  };
  for (const Expected& e :
       {Expected{32, -22.5, 22.5}, Expected{64, -24.33, 2.0}, Expected{128, -25.0, 15.0}}) {
    const auto table = lidar_beam_table(e.beams);
    ASSERT_EQ(table.size(), static_cast<std::size_t>(e.beams));
    EXPECT_NEAR(deg_from_rad(table.front().elevation), e.low_deg, 1e-9);
    EXPECT_NEAR(deg_from_rad(table.back().elevation), e.high_deg, 1e-9);
    EXPECT_TRUE(std::is_sorted(table.begin(), table.end(), [](const auto& a, const auto& b) {
      return a.elevation < b.elevation;
    }));
  }
  EXPECT_THROW(lidar_beam_table(16), std::invalid_argument);
}

TEST(LidarModel, FlatSceneRangeResidualHasTheConfiguredNoise) {
  const Route route = flat_straight_route(300.0);
  const World world = flat_world(route);
  const WorldScene scene(world);
  const VehicleStates states = straight_states(100.0, 0.0, 0.3);  // standing still
  const double height = 1.8;
  const LidarSimulator lidar(scene, states, mounting(height), test_options(), 3);
  std::vector<double> residuals;
  for (std::size_t k = 0; k < lidar.sweep_count(); ++k) {
    for (const io::LidarPoint& p : lidar.sweep(k).cloud.points) {
      const Eigen::Vector3d direction = position(p).normalized();
      residuals.push_back(position(p).norm() - height / -direction.z());  // ground at z = 0
    }
  }
  ASSERT_GT(residuals.size(), 10000u);
  const double mean = std::accumulate(residuals.begin(), residuals.end(), 0.0) / residuals.size();
  double variance = 0.0;
  for (const double r : residuals) variance += (r - mean) * (r - mean);
  const double std_m = std::sqrt(variance / (residuals.size() - 1));
  // n > 10^4 gives the sample std to 1 %; 4 % allows for the mesh and float rounding too.
  EXPECT_NEAR(std_m, 0.02, 0.04 * 0.02);
  EXPECT_NEAR(mean, 0.0, 1e-3);
}

TEST(LidarModel, PointsFollowTheBeamTableAndTheSweepTime) {
  const Route route = flat_straight_route(300.0);
  const World world = flat_world(route);
  const WorldScene scene(world);
  LidarOptions options = test_options(2.0);
  options.range_noise_m = 0.0;
  const VehicleStates states = straight_states(100.0, 0.0, 0.2);
  const LidarSimulator lidar(scene, states, mounting(1.9), options, 3);
  const LidarSweep sweep = lidar.sweep(0);
  const auto table = lidar_beam_table(64);
  const double column_period = 0.1 / options.columns();
  std::vector<bool> ring_seen(table.size(), false);
  float previous_t = 0.0f;
  for (const io::LidarPoint& p : sweep.cloud.points) {
    ASSERT_LT(p.ring, table.size());
    ring_seen[p.ring] = true;
    EXPECT_NEAR(std::atan2(p.z, std::hypot(p.x, p.y)), table[p.ring].elevation, 1e-5);
    const int column = static_cast<int>(std::lround(p.t / column_period));
    const double azimuth = kPi - column * rad_from_deg(2.0) + table[p.ring].azimuth_offset;
    EXPECT_THAT(std::atan2(p.y, p.x), AngleNearDeg(azimuth, 1e-3));
    EXPECT_GE(p.t, previous_t);
    previous_t = p.t;
  }
  // Every beam pointing 4 deg or more below the horizon reaches the ground within range.
  for (std::size_t b = 0; b < table.size(); ++b) {
    if (table[b].elevation < rad_from_deg(-4.0)) {
      EXPECT_TRUE(ring_seen[b]) << b;
    }
  }
  EXPECT_EQ(sweep.cloud.points.front().t, 0.0f);
  EXPECT_NEAR(sweep.cloud.points.back().t, 0.1 - column_period, 1e-6);
}

TEST(LidarModel, PitchedDownLidarSeesTheGroundNormalTiltedTowardsMinusX) {
  const Route route = flat_straight_route(300.0);
  const World world = flat_world(route);
  const WorldScene scene(world);
  const EulerAngles angles{rad_from_deg(-2.0), rad_from_deg(3.0), rad_from_deg(4.0)};
  const VehicleStates states = straight_states(100.0, 0.0, 0.2);
  const LidarSimulator lidar(scene, states, mounting(1.7, angles), test_options(), 5);
  std::vector<Eigen::Vector3d> points;
  for (const io::LidarPoint& p : lidar.sweep(0).cloud.points) points.push_back(position(p));
  const auto [normal, offset] = fit_plane(points);
  EXPECT_LT(normal.x(), 0.0);
  EXPECT_THAT(std::asin(-normal.x()), AngleNearDeg(angles.pitch, 0.02));  // DESIGN §2
  EXPECT_THAT(std::atan2(normal.y(), normal.z()), AngleNearDeg(angles.roll, 0.02));
  EXPECT_NEAR(offset, 1.7, 2e-3);
}

TEST(LidarModel, SweepIsDistortedByTheCarsMotion) {
  const Route route = flat_straight_route(300.0);
  World world = flat_world(route);
  WorldObject wall;  // a building behind the car, its face at x = 30
  wall.id = 1;
  wall.kind = ObjectKind::kBuilding;
  wall.material = standard_material(Surface::kFacade);
  wall.world_from_object.translation() = Eigen::Vector3d(27.5, 0.0, 0.0);
  wall.size = {5.0, 40.0, 10.0};
  world.objects.push_back(wall);
  const WorldScene scene(world);
  const VehicleStates states = straight_states(60.0, 15.0, 0.3);
  const Eigen::Isometry3d vehicle_from_lidar = mounting(1.8);
  LidarOptions options = test_options(0.5);
  options.range_noise_m = 0.0;
  const LidarSimulator lidar(scene, states, vehicle_from_lidar, options, 7);
  const LidarSweep sweep = lidar.sweep(1);
  const Eigen::Isometry3d at_start =
      world_from_vehicle_at(states, sweep.start_time) * vehicle_from_lidar;
  double low = 1e9, high = -1e9;
  int on_wall = 0;
  for (std::size_t i = 0; i < sweep.cloud.points.size(); ++i) {
    if (sweep.object_ids[i] != 1) continue;
    const io::LidarPoint& p = sweep.cloud.points[i];
    const Eigen::Isometry3d at_time =
        world_from_vehicle_at(states, sweep.start_time + p.t) * vehicle_from_lidar;
    EXPECT_NEAR((at_time * position(p)).x(), 30.0, 1e-3);
    const double x_if_static = (at_start * position(p)).x();
    low = std::min(low, x_if_static);
    high = std::max(high, x_if_static);
    ++on_wall;
  }
  ASSERT_GT(on_wall, 100);
  // Seen at the sweep's start and at its end, 0.1 s x 15 m/s apart.
  EXPECT_NEAR(high - low, 1.5, 0.1);
}

TEST(LidarModel, RoadPointsLieOnTheRoadSurfaceOfAGradedCamberedDrive) {
  const UrbanDrive drive = urban_drive(2, 12.0);
  double steepest_grade = 0.0, steepest_crossfall = 0.0;
  for (const VehicleState& state : drive.states) {
    const RoutePoint here = drive.route.at(state.arc_length);
    steepest_grade = std::max(steepest_grade, std::abs(here.grade));
    steepest_crossfall = std::max(steepest_crossfall, std::abs(here.crossfall));
  }
  EXPECT_GT(steepest_grade, 0.01);  // the check means something
  EXPECT_GT(steepest_crossfall, 0.003);
  const WorldScene scene(drive.world);
  for (const double noise : {0.0, 0.02}) {
    LidarOptions options = test_options(0.5);
    options.range_noise_m = noise;
    const LidarSimulator lidar(scene, drive.states, drive.vehicle_from_lidar, options, 9);
    double largest = 0.0, sum_squares = 0.0;
    std::size_t road_points = 0;
    for (const std::size_t k : {10u, 50u, 90u}) {
      const LidarSweep sweep = lidar.sweep(k);
      const double s_car =
          drive.states[static_cast<std::size_t>(std::lround(sweep.start_time * 100.0))].arc_length;
      for (std::size_t i = 0; i < sweep.cloud.points.size(); ++i) {
        if (drive.world.kind_of(sweep.object_ids[i]) != ObjectKind::kRoad) continue;
        const WorldObject& object = drive.world.objects[sweep.object_ids[i]];
        const io::LidarPoint& p = sweep.cloud.points[i];
        const Eigen::Vector3d p_world =
            world_from_vehicle_at(drive.states, sweep.start_time + p.t) * drive.vehicle_from_lidar *
            position(p);
        const double height = height_above_road(
            drive.route, p_world, s_car, object.strip->s_begin - 1.0, object.strip->s_end + 1.0);
        largest = std::max(largest, std::abs(height));
        sum_squares += height * height;
        ++road_points;
      }
    }
    ASSERT_GT(road_points, 5000u);
    // Without noise only the mesh and float rounding remain (< 1 mm measured). Range noise moves a
    // point along its beam, which points at most 25 deg down: vertically |noise| x sin(25 deg)
    // at most, so 2.5 sigma bounds every point and sigma / 2 the rms.
    EXPECT_LT(largest, noise == 0.0 ? 0.002 : 2.5 * noise) << "noise " << noise;
    EXPECT_LT(std::sqrt(sum_squares / road_points), noise == 0.0 ? 5e-4 : 0.5 * noise) << noise;
  }
}

TEST(LidarModel, SameSeedSamePointsAndPaintIsBrighterThanAsphalt) {
  const UrbanDrive drive = urban_drive(4, 6.0);
  const WorldScene scene(drive.world);
  const LidarOptions options = test_options(0.5);
  const LidarSimulator a(scene, drive.states, drive.vehicle_from_lidar, options, 21);
  const LidarSimulator b(scene, drive.states, drive.vehicle_from_lidar, options, 21);
  const LidarSimulator c(scene, drive.states, drive.vehicle_from_lidar, options, 22);
  const LidarSweep first = a.sweep(20), again = b.sweep(20), other = c.sweep(20);
  EXPECT_TRUE(same_points(first.cloud, again.cloud));
  EXPECT_EQ(first.object_ids, again.object_ids);
  EXPECT_FALSE(same_points(first.cloud, other.cloud));
  double paint = 0.0, asphalt = 0.0;
  int paint_n = 0, asphalt_n = 0;
  for (std::size_t i = 0; i < first.cloud.points.size(); ++i) {
    const ObjectKind kind = drive.world.kind_of(first.object_ids[i]);
    if (kind == ObjectKind::kLaneMarking) paint += first.cloud.points[i].intensity, ++paint_n;
    if (kind == ObjectKind::kRoad) asphalt += first.cloud.points[i].intensity, ++asphalt_n;
  }
  ASSERT_GT(paint_n, 20);
  EXPECT_GT(paint / paint_n, 3.0 * asphalt / asphalt_n);
}

}  // namespace
}  // namespace x2car::sim
