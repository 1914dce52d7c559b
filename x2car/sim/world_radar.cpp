#include "x2car/sim/world_radar.hpp"

#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"

namespace x2car::sim {
namespace {

Eigen::Vector3d reflector_point(const Eigen::Isometry3d& world_from_object, double height) {
  return world_from_object.translation() + Eigen::Vector3d(0.0, 0.0, height);
}

// A mover's path: one sample per period while it is on its road. Its presence is one interval
// (constant speed along a stretch of road), so the samples are contiguous.
RadarMover radar_mover(const World& world, const MovingObject& mover, double start_time,
                       double end_time, const WorldRadarOptions& options) {
  RadarMover target{static_cast<int>(mover.id), mover.material.radar_cross_section_dbsm, {}};
  const auto steps =
      static_cast<long>(std::ceil((end_time - start_time) / options.mover_sample_period_s));
  for (long k = 0; k <= steps; ++k) {
    const double time =
        k == steps ? end_time : start_time + static_cast<double>(k) * options.mover_sample_period_s;
    if (!world.mover_present(mover, time)) continue;
    target.path.push_back(
        {time, reflector_point(world.mover_pose(mover, time), options.reflector_height_m),
         world.mover_velocity(mover, time)});
  }
  return target;
}

}  // namespace

void WorldRadarOptions::Check() const {
  const OptionsCheck check("WorldRadarOptions");
  check.non_negative("reflector_height_m", reflector_height_m);
  // Every mover is sampled this often over the whole drive: a period below a millisecond only
  // exhausts memory (radar scans are 50 ms apart).
  check.at_least("mover_sample_period_s", mover_sample_period_s, 1e-3);
  check.finite("mover_sample_period_s", mover_sample_period_s);
}

bool is_radar_target(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kPole:
    case ObjectKind::kTrafficSign:
    case ObjectKind::kGuardRailPost:
    case ObjectKind::kParkedCar:
    case ObjectKind::kCar:
    case ObjectKind::kCyclist:
      return true;
    default:
      return false;
  }
}

RadarScene radar_scene_from_world(const World& world, double start_time, double end_time,
                                  const WorldRadarOptions& options) {
  options.Check();
  if (!(end_time >= start_time)) {
    throw std::invalid_argument("radar_scene_from_world: end_time before start_time");
  }
  RadarScene scene;
  for (const WorldObject& object : world.objects) {
    if (!is_radar_target(object.kind)) continue;
    scene.reflectors.push_back(
        {static_cast<int>(object.id),
         reflector_point(object.world_from_object, options.reflector_height_m),
         object.material.radar_cross_section_dbsm});
  }
  for (const MovingObject& mover : world.movers) {
    if (!is_radar_target(mover.kind)) continue;
    RadarMover target = radar_mover(world, mover, start_time, end_time, options);
    // RadarMover::at interpolates between samples: one sample alone is too short a visit.
    if (target.path.size() >= 2) scene.movers.push_back(std::move(target));
  }
  return scene;
}

}  // namespace x2car::sim
