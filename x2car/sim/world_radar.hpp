// The radar's view of the 3-D world (world.hpp): its objects as the point targets of
// radar_scene.hpp, so that the radar sees the same poles, signs, parked cars and traffic as the
// LiDAR does.
//
//   static targets (RadarReflector): poles, traffic signs, guard-rail posts, parked cars
//   moving targets (RadarMover):     moving cars and cyclists, sampled while on their road
//
// Each target is one point reflector at its footprint's centre, reflector_height_m above the
// ground, with the object's radar cross-section (Material::radar_cross_section_dbsm); ids are the
// world's object ids. Buildings, trees, the road and the guard rails' bands are left out: they are
// extended surfaces that a tracking radar reports as clutter or not at all, and the radar model
// has no extended targets (radar_model.hpp, "Not modelled"). Occlusion is not modelled either.
#pragma once

#include "x2car/sim/radar_scene.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim {

struct WorldRadarOptions {
  double reflector_height_m = 0.5;      // above the object's ground point, about a bumper's [m]
  double mover_sample_period_s = 0.05;  // of the movers' paths (linear between samples) [s], > 0

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// Whether the radar reports objects of this kind as targets.
bool is_radar_target(ObjectKind kind);

// The world's radar targets for a drive from `start_time` to `end_time` [s]: every static target,
// and every mover present at some sample time k * period within [start_time, end_time] (the end
// always sampled), sampled while it is present. Same arguments, same scene.
RadarScene radar_scene_from_world(const World& world, double start_time, double end_time,
                                  const WorldRadarOptions& options = {});

}  // namespace x2car::sim
