#include "x2car/sim/world.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <stdexcept>

#include "x2car/sim/test_drives.hpp"
#include "x2car/sim/vehicle_motion.hpp"
#include "x2car/sim/world_mesh.hpp"

namespace x2car::sim {
namespace {

using testing::world_drive;

std::map<ObjectKind, int> count_kinds(const World& world) {
  std::map<ObjectKind, int> counts;
  for (const WorldObject& object : world.objects) ++counts[object.kind];
  for (const MovingObject& mover : world.movers) ++counts[mover.kind];
  return counts;
}

// Horizontal distance from a point to the nearest road station's centre line point [m], and that
// station.
const RoadStation& nearest_station(const RoadLayout& road, const Eigen::Vector3d& point) {
  const RoadStation* best = &road.stations.front();
  for (const RoadStation& station : road.stations) {
    if ((station.centre - point).head<2>().norm() < (best->centre - point).head<2>().norm()) {
      best = &station;
    }
  }
  return *best;
}

TEST(World, CarDrivesOnTheRoadSurface) {
  const testing::WorldDrive drive = world_drive(Scenario::kMixed, 120.0, 5);
  for (std::size_t i = 0; i < drive.states.size(); i += 50) {
    const VehicleState& state = drive.states[i];
    const RoadStation station = drive.world.road.station_at(state.arc_length);
    const Eigen::Vector3d on_road = station.surface_point(station.route_offset);
    EXPECT_LT((on_road - state.world_from_vehicle.translation()).norm(), 2e-3) << state.time;
    // The surface normal is the vehicle's z axis up to the body's roll and pitch (0.5 deg per
    // m/s^2 of lateral, 0.4 deg per m/s^2 of longitudinal acceleration).
    const Eigen::Vector3d normal = station.surface_rotation().col(2);
    const Eigen::Vector3d vehicle_z = state.world_from_vehicle.linear().col(2);
    EXPECT_LT(std::acos(std::min(1.0, normal.dot(vehicle_z))), rad_from_deg(2.5)) << state.time;
  }
}

TEST(World, UrbanWorldHasEveryKindOfObject) {
  const testing::WorldDrive drive = world_drive(Scenario::kUrban, 60.0, 1);
  const auto counts = count_kinds(drive.world);
  for (const ObjectKind kind :
       {ObjectKind::kRoad, ObjectKind::kLaneMarking, ObjectKind::kCurb, ObjectKind::kSidewalk,
        ObjectKind::kTerrain, ObjectKind::kBuilding, ObjectKind::kPole, ObjectKind::kTrafficSign,
        ObjectKind::kTree, ObjectKind::kParkedCar, ObjectKind::kCar, ObjectKind::kCyclist}) {
    EXPECT_GT(counts.count(kind) ? counts.at(kind) : 0, 0) << to_string(kind);
  }
  EXPECT_EQ(counts.count(ObjectKind::kGuardRail), 0u);
  EXPECT_GT(counts.at(ObjectKind::kBuilding), 20);
  for (std::size_t i = 0; i < drive.world.objects.size(); ++i) {
    EXPECT_EQ(drive.world.objects[i].id, i);
  }
  for (const MovingObject& mover : drive.world.movers) {
    EXPECT_EQ(drive.world.kind_of(mover.id), mover.kind);
  }
}

TEST(World, HighwayHasGuardRailsAndNoSidewalks) {
  const testing::WorldDrive drive = world_drive(Scenario::kHighway, 60.0, 2);
  const auto counts = count_kinds(drive.world);
  EXPECT_GT(counts.at(ObjectKind::kGuardRail), 0);
  EXPECT_GT(counts.at(ObjectKind::kGuardRailPost), 500);
  EXPECT_GT(counts.at(ObjectKind::kCar), 10);
  EXPECT_EQ(counts.count(ObjectKind::kSidewalk), 0u);
  EXPECT_EQ(counts.count(ObjectKind::kBuilding), 0u);
}

TEST(World, SolidsStandClearOfEveryStretchOfRoad) {
  const testing::WorldDrive drive = world_drive(Scenario::kUrban, 90.0, 3);
  for (const WorldObject& object : drive.world.objects) {
    if (object.strip || object.kind == ObjectKind::kParkedCar ||
        object.kind == ObjectKind::kGuardRailPost) {
      continue;
    }
    const Eigen::Vector3d centre = object.world_from_object.translation();
    const RoadStation& station = nearest_station(drive.world.road, centre);
    const CrossSection& section = drive.world.road.segment_at(station.s).section;
    const double distance = (station.centre - centre).head<2>().norm();
    const double needed = object.kind == ObjectKind::kBuilding
                              ? section.clear_edge + 0.5 * object.size.y()
                              : section.asphalt_edge;
    EXPECT_GE(distance, needed - 1e-6) << to_string(object.kind) << " " << object.id;
  }
}

TEST(World, SameSeedSameWorld) {
  const testing::WorldDrive a = world_drive(Scenario::kUrban, 30.0, 11);
  const testing::WorldDrive b = world_drive(Scenario::kUrban, 30.0, 11);
  ASSERT_EQ(a.world.objects.size(), b.world.objects.size());
  ASSERT_EQ(a.world.movers.size(), b.world.movers.size());
  for (std::size_t i = 0; i < a.world.objects.size(); ++i) {
    EXPECT_TRUE(
        a.world.objects[i].world_from_object.isApprox(b.world.objects[i].world_from_object, 0.0));
    EXPECT_EQ(a.world.objects[i].size, b.world.objects[i].size);
  }
  const testing::WorldDrive c = world_drive(Scenario::kUrban, 30.0, 12);
  auto mean_x = [](const World& world) {
    double sum = 0.0;
    for (const WorldObject& object : world.objects)
      sum += object.world_from_object.translation().x();
    return sum / static_cast<double>(world.objects.size());
  };
  EXPECT_GT(std::abs(mean_x(a.world) - mean_x(c.world)), 1.0);
}

TEST(World, MoversDriveTheirLanesAndKeepClearOfTheCar) {
  const testing::WorldDrive drive = world_drive(Scenario::kHighway, 60.0, 4);
  const World& world = drive.world;
  ASSERT_GT(world.movers.size(), 20u);
  int checked = 0;
  for (const MovingObject& mover : world.movers) {
    for (double t = 0.0; t <= 60.0; t += 5.0) {
      if (!world.mover_present(mover, t - 1.0) || !world.mover_present(mover, t + 1.0)) continue;
      const Eigen::Isometry3d pose = world.mover_pose(mover, t);
      const RoadStation station = world.road.station_at(mover.s_at_zero + mover.speed * t);
      EXPECT_LT((pose.translation() - station.surface_point(mover.lateral)).norm(), 1e-9);
      // It faces its way of travel, and moves at its speed along s, up to the lateral factor of
      // highway curves (1 - curvature x offset from the route: R >= 400 m, offset <= 25 m).
      const Eigen::Vector3d velocity = world.mover_velocity(mover, t);
      EXPECT_NEAR(velocity.norm(), std::abs(mover.speed), 0.07 * std::abs(mover.speed));
      EXPECT_GT(velocity.dot(pose.linear().col(0)), 0.0);
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
  for (std::size_t i = 0; i < drive.states.size(); i += 10) {
    const VehicleState& state = drive.states[i];
    const double own_lateral = world.road.station_at(state.arc_length).route_offset;
    for (const MovingObject& mover : world.movers) {
      const double s = mover.s_at_zero + mover.speed * state.time;
      if (!world.mover_present(mover, state.time) || std::abs(mover.lateral - own_lateral) > 1.0) {
        continue;
      }
      EXPECT_GT(std::abs(s - state.arc_length), 5.0)
          << "mover " << mover.id << " at " << state.time;
    }
  }
}

TEST(World, MeshTablesMatchTheTriangles) {
  const testing::WorldDrive drive = world_drive(Scenario::kUrban, 20.0, 6);
  const TriangleMesh mesh = mesh_static_world(drive.world, Eigen::Vector3d::Zero());
  ASSERT_GT(mesh.triangles.size(), 10000u);
  EXPECT_EQ(mesh.triangle_object.size(), mesh.triangles.size());
  EXPECT_EQ(mesh.triangle_surface.size(), mesh.triangles.size());
  EXPECT_EQ(mesh.triangle_reflectivity.size(), mesh.triangles.size());
  for (const auto& triangle : mesh.triangles) {
    for (const std::uint32_t v : triangle) ASSERT_LT(v, mesh.vertices.size());
  }
  for (const std::uint32_t id : mesh.triangle_object) ASSERT_LT(id, drive.world.objects.size());
}

TEST(WorldOptions, RejectBadValues) {
  WorldOptions options;
  EXPECT_NO_THROW(options.Check());
  options.roadside.building_frontage = 1.5;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.traffic.cyclist_min_speed_mps = 10.0;  // above the max
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.road.lane_width_m = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

// Values a reviewer's --config took past 60 s or into bad_alloc on a 5 s drive: each spacing,
// density and step is bounded now, and 0 still turns a kind of object off.
TEST(WorldOptions, RejectSpacingsDensitiesAndStepsThatCannotFinish) {
  const auto rejected = [](auto change) {
    WorldOptions options;
    change(options);
    EXPECT_THROW(options.Check(), std::invalid_argument);
  };
  rejected([](WorldOptions& o) { o.roadside.pole_spacing_m = 1e-6; });
  rejected([](WorldOptions& o) { o.roadside.sign_spacing_m = 0.1; });
  rejected([](WorldOptions& o) { o.roadside.tree_spacing_m = 0.4; });
  rejected([](WorldOptions& o) { o.roadside.guard_rail_post_spacing_m = 1e-5; });
  rejected(
      [](WorldOptions& o) { o.roadside.pole_spacing_m = std::numeric_limits<double>::infinity(); });
  rejected([](WorldOptions& o) {
    o.roadside.building_min_length_m = 1e-6;
    o.roadside.building_max_length_m = 1e-6;
  });
  rejected([](WorldOptions& o) { o.roadside.terrain_half_width_m = 1e9; });
  rejected([](WorldOptions& o) { o.road.max_station_step_m = 1e-7; });
  rejected([](WorldOptions& o) { o.road.highway_lanes = 1000000; });
  rejected([](WorldOptions& o) { o.traffic.oncoming_cars_per_km = 1e7; });
  rejected([](WorldOptions& o) { o.traffic.cyclists_per_km = 501.0; });
  rejected([](WorldOptions& o) { o.traffic.highway_cars_per_km_lane = 1e7; });
  rejected([](WorldOptions& o) { o.traffic.highway_max_speed_mps = 1e12; });
  WorldOptions none;
  none.roadside.pole_spacing_m = 0.0;
  none.roadside.sign_spacing_m = 0.0;
  none.roadside.tree_spacing_m = 0.0;
  none.roadside.guard_rail_post_spacing_m = 0.0;
  none.traffic.oncoming_cars_per_km = 0.0;
  EXPECT_NO_THROW(none.Check());
  WorldOptions dense;
  dense.roadside.pole_spacing_m = 0.5;
  dense.traffic.oncoming_cars_per_km = 500.0;
  dense.road.max_station_step_m = 0.05;
  EXPECT_NO_THROW(dense.Check());
}

}  // namespace
}  // namespace x2car::sim
