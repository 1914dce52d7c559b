#include "x2car/sim/radar_scene.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::sim {
namespace {

using testing::straight_drive;

// Sideways offset of a point from the straight path through the origin along heading (left > 0).
double lateral(const Eigen::Vector3d& p, double heading) {
  return -std::sin(heading) * p.x() + std::cos(heading) * p.y();
}
double along(const Eigen::Vector3d& p, double heading) {
  return std::cos(heading) * p.x() + std::sin(heading) * p.y();
}

TEST(RadarScene, SameSeedSameScene) {
  const VehicleStates states = straight_drive(20.0, 10.0, 1.0);
  const RadarScene a = generate_radar_scene(states, {}, 9);
  const RadarScene b = generate_radar_scene(states, {}, 9);
  const RadarScene c = generate_radar_scene(states, {}, 10);
  ASSERT_EQ(a.reflectors.size(), b.reflectors.size());
  ASSERT_EQ(a.movers.size(), b.movers.size());
  for (std::size_t i = 0; i < a.reflectors.size(); ++i) {
    EXPECT_EQ(a.reflectors[i].position_world, b.reflectors[i].position_world);
  }
  EXPECT_NE(a.reflectors.front().position_world, c.reflectors.front().position_world);
  a.Check();
}

TEST(RadarScene, PlacesRoadsideObjectsAndTrafficWhereTheOptionsSay) {
  const double heading = 1.0;
  const double speed = 10.0;
  const VehicleStates states = straight_drive(30.0, speed, heading);
  const RadarSceneOptions options;
  const RadarScene scene = generate_radar_scene(states, options, 4, 1000);
  std::size_t right = 0, left = 0, parked = 0;
  for (const RadarReflector& r : scene.reflectors) {
    EXPECT_GE(r.object_id, 1000);
    const double y = lateral(r.position_world, heading);
    const double x = along(r.position_world, heading);
    EXPECT_GE(x, -options.margin_m - 1e-9);
    EXPECT_LE(x, speed * 30.0 + options.margin_m + 1e-9);
    EXPECT_NEAR(r.position_world.z(), options.reflector_height_m, 1e-12);
    if (std::abs(y + options.parked_offset_m) < 1e-9) {
      ++parked;
    } else if (y < 0.0) {
      ++right;
      EXPECT_GE(-y, options.post_min_offset_m - 1e-9);
      EXPECT_LE(-y, options.post_max_offset_m + 1e-9);
    } else {
      ++left;
      EXPECT_GE(y, options.lane_width_m + options.post_min_offset_m - 1e-9);
      EXPECT_LE(y, options.lane_width_m + options.post_max_offset_m + 1e-9);
    }
  }
  // 900 m of roadside, posts every 15-45 m per side, parked cars every 40-150 m.
  EXPECT_GT(right, 20u);
  EXPECT_GT(left, 20u);
  EXPECT_GT(parked, 5u);

  std::size_t oncoming = 0, same_way = 0;
  for (const RadarMover& m : scene.movers) {
    for (const MoverSample& s : m.path) {
      const double v_along =
          std::cos(heading) * s.velocity_enu.x() + std::sin(heading) * s.velocity_enu.y();
      const double y = lateral(s.position_world, heading);
      if (v_along < 0.0) {
        ++oncoming;
        EXPECT_NEAR(y, options.lane_width_m, 1e-9);  // in the left lane
      } else {
        ++same_way;
        EXPECT_LT(y, 1e-9);  // in the car's lane or on its right edge
      }
    }
  }
  EXPECT_GT(oncoming, 500u);
  EXPECT_GT(same_way, 500u);
}

TEST(RadarScene, CarsAheadKeepTheirGapAndNeverReverse) {
  const VehicleStates states = straight_drive(60.0, 8.0, 0.0);
  RadarSceneOptions options;
  options.cars_behind = 0;
  const RadarScene scene = generate_radar_scene(states, options, 2);
  std::size_t checked = 0;
  for (const RadarMover& m : scene.movers) {
    if (std::abs(m.path.front().position_world.y()) > 1e-9) continue;  // not in the car's lane
    ++checked;
    for (std::size_t j = 0; j < m.path.size(); ++j) {
      const MoverSample& s = m.path[j];
      EXPECT_GE(s.position_world.x() - 8.0 * s.time, options.min_gap_m - 1e-6);
      EXPECT_NEAR(s.position_world.y(), 0.0, 1e-9);
      EXPECT_GE(s.velocity_enu.x(), -1e-9);
    }
  }
  EXPECT_GE(checked, 2u);  // two queue slots, each filled at least once in a minute
}

TEST(RadarScene, TrafficDensityScalesTheMovers) {
  const VehicleStates states = straight_drive(30.0, 10.0, 0.0);
  RadarSceneOptions sparse;
  sparse.traffic_density = 0.5;
  RadarSceneOptions dense;
  dense.traffic_density = 2.0;
  EXPECT_GT(generate_radar_scene(states, dense, 1).movers.size(),
            2 * generate_radar_scene(states, sparse, 1).movers.size());
}

TEST(RadarMover, InterpolatesInsideItsPathAndIsAbsentOutside) {
  RadarMover mover{3, 10.0, {{1.0, {0, 0, 0}, {2, 0, 0}}, {2.0, {2, 4, 0}, {4, 0, 0}}}};
  const auto mid = mover.at(1.25);
  ASSERT_TRUE(mid.has_value());
  EXPECT_EQ(mid->position_world, Eigen::Vector3d(0.5, 1.0, 0.0));
  EXPECT_EQ(mid->velocity_enu, Eigen::Vector3d(2.5, 0.0, 0.0));
  EXPECT_TRUE(mover.at(2.0).has_value());
  EXPECT_FALSE(mover.at(0.99).has_value());
  EXPECT_FALSE(mover.at(2.01).has_value());
}

TEST(RadarScene, CheckRejectsRepeatedIdsAndUnorderedPaths) {
  RadarScene scene;
  scene.reflectors = {{1, {0, 0, 0}, 0.0}, {2, {1, 0, 0}, 0.0}};
  scene.Check();
  scene.movers = {{2, 5.0, {{0.0, {0, 0, 0}, {0, 0, 0}}}}};
  EXPECT_THROW(scene.Check(), std::invalid_argument);
  scene.movers = {{3, 5.0, {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.0, {0, 0, 0}, {0, 0, 0}}}}};
  EXPECT_THROW(scene.Check(), std::invalid_argument);
  scene.movers.clear();
  scene.reflectors[0].object_id = -4;
  EXPECT_THROW(scene.Check(), std::invalid_argument);
}

TEST(RadarSceneOptions, CheckRejectsBadValues) {
  RadarSceneOptions options;
  options.Check();
  options.traffic_density = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.post_min_spacing_m = 60.0;  // above the maximum
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.cars_ahead = -1;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_THROW(generate_radar_scene(VehicleStates(1), {}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::sim
