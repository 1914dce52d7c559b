// What the simulated radar sees (radar_model.hpp): point reflectors in the local ENU world, static
// ones (poles, signs, parked cars, guard-rail posts) and moving ones (cars, cyclists) on sampled
// paths. The 3-D world's object list is adapted to this; generate_radar_scene makes a scene of its
// own along the car's drive, for tests and for drives without a world.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

// A static point target.
struct RadarReflector {
  int object_id = 0;                                         // >= 0, unique within a scene
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();  // ENU [m]
  double rcs_dbsm = 0.0;                                     // radar cross-section [dBsm]
};

// One sample of a moving target's path.
struct MoverSample {
  double time = 0.0;                                         // [s] on the drive's clock
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();  // ENU [m]
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();    // [m/s]
};

// A moving point target; it exists from its first sample's time to its last's.
struct RadarMover {
  int object_id = 0;              // >= 0, unique within a scene (shared with the reflectors)
  double rcs_dbsm = 0.0;          // [dBsm]
  std::vector<MoverSample> path;  // times strictly increasing

  // Position and velocity at `time`, each linear between the two samples around it; nullopt
  // outside the path's time span (the mover is not there).
  std::optional<MoverSample> at(double time) const;
};

struct RadarScene {
  std::vector<RadarReflector> reflectors;
  std::vector<RadarMover> movers;

  // Throws std::invalid_argument for a repeated or negative object id, a non-finite value, or a
  // path whose times do not strictly increase.
  void Check() const;
};

// How generate_radar_scene populates the roadside and the traffic. Offsets are sideways from the
// car's own driven path, positive to the left (the car drives in the right-hand lane of a two-lane
// road; oncoming traffic is on the left). Spacings are drawn uniformly in [min, max].
struct RadarSceneOptions {
  double lane_width_m = 3.5;  // [m]

  // Posts, poles and signs along both roadsides.
  double post_min_spacing_m = 20.0;  // along each side [m]
  double post_max_spacing_m = 50.0;  // [m]
  double post_min_offset_m = 4.0;    // right side: offset -[min, max]; left side: one lane
  double post_max_offset_m = 7.0;    // further, lane_width + [min, max] [m]
  double post_min_rcs_dbsm = 0.0;    // [dBsm]
  double post_max_rcs_dbsm = 10.0;   // [dBsm]

  // Parked cars on the right, at offset -parked_offset_m.
  double parked_min_spacing_m = 40.0;   // [m]
  double parked_max_spacing_m = 150.0;  // [m]
  double parked_offset_m = 3.8;         // [m]
  double car_min_rcs_dbsm = 8.0;        // every car, parked or moving [dBsm]
  double car_max_rcs_dbsm = 15.0;       // [dBsm]

  // Scales the number of moving cars and cyclists (spacings are divided by it), > 0. The share of
  // detections on moving objects grows with it: about 40 % on an urban drive at 1.
  double traffic_density = 1.0;

  // Oncoming cars in the left lane at a constant speed each (spacings at their start).
  double oncoming_min_spacing_m = 12.0;        // between oncoming cars [m]
  double oncoming_max_spacing_m = 48.0;        // [m]
  double oncoming_min_speed_mps = 20.0 / 3.6;  // [m/s]
  double oncoming_max_speed_mps = 50.0 / 3.6;  // [m/s]

  // Cars in the car's own lane: `cars_ahead` queued in front of it and `cars_behind` behind it,
  // each keeping a gap of gap_m + time_gap_s * the car's speed (never reversing), present for
  // spells of [min, max] presence, absent for [min, max] absence (a car turning off, another
  // joining).
  int cars_ahead = 3;
  int cars_behind = 1;
  double min_gap_m = 6.0;        // [m]
  double max_gap_m = 12.0;       // [m]
  double min_time_gap_s = 1.0;   // [s]
  double max_time_gap_s = 2.5;   // [s]
  double min_presence_s = 15.0;  // [s]
  double max_presence_s = 60.0;  // [s]
  double min_absence_s = 2.0;    // [s]
  double max_absence_s = 15.0;   // [s]

  // Cyclists on the right edge of the car's lane, riding its way.
  double cyclist_min_spacing_m = 50.0;   // [m]
  double cyclist_max_spacing_m = 150.0;  // [m]
  double cyclist_offset_m = 2.4;         // offset -cyclist_offset_m [m]
  double cyclist_min_speed_mps = 3.0;    // [m/s]
  double cyclist_max_speed_mps = 7.0;    // [m/s]
  double cyclist_min_rcs_dbsm = -3.0;    // [dBsm]
  double cyclist_max_rcs_dbsm = 3.0;     // [dBsm]

  double reflector_height_m = 0.5;  // above the road, of every target [m]
  // The scene reaches this far beyond both ends of the drive, and oncoming cars and cyclists exist
  // only while within this distance of the car along its path (> the radar's range) [m].
  double margin_m = 300.0;
  double mover_sample_period_s = 0.1;  // of the movers' paths [s]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// A scene along the drive `states` (the car's true motion, times strictly increasing, >= 2
// states): the path of the car's origin, continued straight for margin_m beyond both ends, with
// roadside posts, parked cars and traffic as the options say. Object ids count from
// `first_object_id`. The same arguments give the same scene on every platform. Throws
// std::invalid_argument on bad options or states. Not modelled: the road network's other streets,
// traffic rules (oncoming cars and cyclists keep their speed through intersections), collisions.
RadarScene generate_radar_scene(const VehicleStates& states, const RadarSceneOptions& options,
                                std::uint64_t seed, int first_object_id = 0);

}  // namespace x2car::sim
