#include "x2car/sim/world_radar.hpp"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "x2car/sim/test_drives.hpp"
#include "x2car/sim/vehicle_motion.hpp"

namespace x2car::sim {
namespace {

using testing::world_drive;

TEST(WorldRadar, EveryStaticTargetBecomesAReflectorAtItsGroundPoint) {
  const testing::WorldDrive drive = world_drive(Scenario::kMixed, 60.0, 4);
  const RadarScene scene = radar_scene_from_world(drive.world, 0.0, drive.states.back().time);
  EXPECT_NO_THROW(scene.Check());
  std::set<ObjectKind> kinds;
  std::size_t targets = 0;
  for (const WorldObject& object : drive.world.objects) targets += is_radar_target(object.kind);
  ASSERT_EQ(scene.reflectors.size(), targets);
  for (const RadarReflector& reflector : scene.reflectors) {
    const WorldObject& object =
        drive.world.objects.at(static_cast<std::size_t>(reflector.object_id));
    kinds.insert(object.kind);
    EXPECT_EQ(reflector.rcs_dbsm, object.material.radar_cross_section_dbsm);
    const Eigen::Vector3d offset =
        reflector.position_world - object.world_from_object.translation();
    EXPECT_LT((offset - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-12);
  }
  // A mixed drive has urban and highway roadsides.
  for (const ObjectKind kind : {ObjectKind::kPole, ObjectKind::kTrafficSign,
                                ObjectKind::kGuardRailPost, ObjectKind::kParkedCar}) {
    EXPECT_TRUE(kinds.contains(kind)) << to_string(kind);
  }
}

TEST(WorldRadar, MoversFollowTheWorldsTrafficWhilePresent) {
  const testing::WorldDrive drive = world_drive(Scenario::kUrban, 30.0, 2);
  const double end = drive.states.back().time;
  const RadarScene scene = radar_scene_from_world(drive.world, 0.0, end);
  ASSERT_FALSE(scene.movers.empty());
  EXPECT_LE(scene.movers.size(), drive.world.movers.size());
  for (const RadarMover& target : scene.movers) {
    const MovingObject& mover = drive.world.movers.at(static_cast<std::size_t>(target.object_id) -
                                                      drive.world.objects.size());
    ASSERT_GE(target.path.size(), 2u);
    for (const MoverSample& sample : target.path) {
      EXPECT_TRUE(drive.world.mover_present(mover, sample.time));
      EXPECT_GE(sample.time, 0.0);
      EXPECT_LE(sample.time, end);
    }
    // Between samples the target is where the world's mover is, within the linear
    // interpolation's error (curves), and moves at its speed.
    const double t = 0.5 * (target.path.front().time + target.path.back().time);
    const std::optional<MoverSample> at = target.at(t);
    ASSERT_TRUE(at.has_value());
    const Eigen::Vector3d expected =
        drive.world.mover_pose(mover, t).translation() + Eigen::Vector3d(0, 0, 0.5);
    EXPECT_LT((at->position_world - expected).norm(), 0.05) << target.object_id;
    EXPECT_NEAR(at->velocity_enu.norm(), std::abs(mover.speed), 0.5 * std::abs(mover.speed));
  }
}

TEST(WorldRadar, RejectsBadOptions) {
  const World world;
  WorldRadarOptions options;
  options.mover_sample_period_s = 0.0;
  EXPECT_THROW(radar_scene_from_world(world, 0.0, 1.0, options), std::invalid_argument);
  // A nanosecond period ended in bad_alloc on a 5 s drive; a millisecond is the least.
  options.mover_sample_period_s = 1e-9;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.mover_sample_period_s = 1e-3;
  EXPECT_NO_THROW(options.Check());
  EXPECT_THROW(radar_scene_from_world(world, 1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::sim
