// generate_world, part 3: moving cars and cyclists. Each drives one stretch of road of one kind at
// a constant speed in a fixed lane: urban oncoming cars in the left lane, cyclists in the right
// bike lane riding the car's way, highway cars and trucks in every lane of both carriageways.
// Movers are spread along their stretch so that the traffic density holds for the whole drive,
// and a mover whose path would come within ego_clearance_m of the car in its lane is dropped.
#include <algorithm>
#include <array>
#include <cmath>

#include "x2car/sim/world_builder.hpp"

namespace x2car::sim::detail {
namespace {

constexpr double kEgoCheckStep = 0.1;  // [s] between the car's states compared with a path

// The car's own track in road coordinates, to keep movers out of its way.
struct EgoTrack {
  std::vector<double> time, s, lateral;
};

EgoTrack ego_track(const RoadLayout& road, std::span<const VehicleState> ego) {
  EgoTrack track;
  double next = -1.0;
  for (const VehicleState& state : ego) {
    if (state.time < next) continue;
    next = state.time + kEgoCheckStep;
    track.time.push_back(state.time);
    track.s.push_back(state.arc_length);
    track.lateral.push_back(road.station_at(state.arc_length).route_offset);
  }
  return track;
}

class TrafficMaker {
 public:
  TrafficMaker(WorldBuilder& builder, std::span<const VehicleState> ego)
      : builder_(builder),
        options_(builder.options.traffic),
        rng_(Random::derive_seed(builder.seed, 21)),
        track_(ego_track(builder.world.road, ego)),
        duration_(ego.empty() ? 0.0 : ego.back().time) {}

  // Movers in one lane of a stretch [a, b]: `per_km` of them [1/km] at speeds in [min, max]
  // [m/s], along s (+1) or against it (-1).
  void lane(double a, double b, double lateral, double direction, double per_km, double min_speed,
            double max_speed, ObjectKind kind) {
    if (per_km <= 0.0 || !(b > a)) return;
    // Spread over the stretch plus what a mover covers during the drive, so that as many enter
    // as leave.
    const double reach = max_speed * duration_;
    const double from = direction > 0.0 ? a - reach : a;
    const double to = direction > 0.0 ? b : b + reach;
    const auto count = static_cast<int>(std::round(per_km * (to - from) / 1000.0));
    for (int i = 0; i < count; ++i) {
      MovingObject mover;
      mover.kind = kind;
      mover.lateral = lateral;
      mover.speed = direction * rng_.uniform(min_speed, max_speed);
      mover.s_at_zero = rng_.uniform(from, to);
      mover.s_min = a;
      mover.s_max = b;
      dress(mover, direction > 0.0 && lateral < 0.0 && kind == ObjectKind::kCar);
      if (clear_of_ego(mover)) add(mover);
    }
  }

 private:
  void dress(MovingObject& mover, bool may_be_truck) {
    if (mover.kind == ObjectKind::kCyclist) {
      mover.size = {1.8, 0.6, 1.7};
      mover.material = standard_material(Surface::kClothing);
      mover.material.radar_cross_section_dbsm = rng_.uniform(-3.0, 3.0);
      return;
    }
    const bool truck = may_be_truck && rng_.uniform01() < 0.15;
    mover.size = truck ? Eigen::Vector3d(12.0, 2.5, 3.8)
                       : Eigen::Vector3d(rng_.uniform(4.0, 5.0), rng_.uniform(1.75, 1.9),
                                         rng_.uniform(1.4, 1.6));
    mover.material = car_material(truck ? 20.0 : rng_.uniform(8.0, 15.0), rng_);
  }

  bool clear_of_ego(const MovingObject& mover) const {
    const double lane_half = 0.75 * builder_.options.road.lane_width_m;
    for (std::size_t i = 0; i < track_.time.size(); ++i) {
      if (std::abs(track_.lateral[i] - mover.lateral) >= lane_half) continue;
      const double s = mover.s_at_zero + mover.speed * track_.time[i];
      if (s < mover.s_min || s > mover.s_max) continue;
      if (std::abs(s - track_.s[i]) < options_.ego_clearance_m + 0.5 * mover.size.x()) return false;
    }
    return true;
  }

  void add(MovingObject mover) {
    World& world = builder_.world;
    mover.id = static_cast<std::uint32_t>(world.movers.size());  // renumbered in add_traffic
    world.movers.push_back(mover);
  }

  WorldBuilder& builder_;
  const TrafficOptions& options_;
  Random rng_;
  EgoTrack track_;
  double duration_;
};

}  // namespace

void add_traffic(WorldBuilder& builder, std::span<const VehicleState> ego) {
  TrafficMaker traffic(builder, ego);
  const TrafficOptions& o = builder.options.traffic;
  for (const RoadSegment& segment : builder.world.road.segments) {
    const CrossSection& section = segment.section;
    const double a = std::max(segment.s_begin, builder.world.road.s_begin());
    const double b = std::min(segment.s_end, builder.world.road.s_end());
    if (section.kind == Scenario::kUrban) {
      traffic.lane(a, b, -section.right_lane_centre(0), -1.0, o.oncoming_cars_per_km,
                   o.urban_min_speed_mps, o.urban_max_speed_mps, ObjectKind::kCar);
      traffic.lane(a, b, -0.5 * (section.edge_line + section.asphalt_edge), 1.0, o.cyclists_per_km,
                   o.cyclist_min_speed_mps, o.cyclist_max_speed_mps, ObjectKind::kCyclist);
      continue;
    }
    for (int k = 0; k < section.lanes; ++k) {
      for (const double direction : {1.0, -1.0}) {
        traffic.lane(a, b, direction * section.right_lane_centre(k), direction,
                     o.highway_cars_per_km_lane, o.highway_min_speed_mps, o.highway_max_speed_mps,
                     ObjectKind::kCar);
      }
    }
  }
  // Ids follow the static objects' (World::movers' comment).
  const auto first = static_cast<std::uint32_t>(builder.world.objects.size());
  for (std::size_t i = 0; i < builder.world.movers.size(); ++i) {
    builder.world.movers[i].id = first + static_cast<std::uint32_t>(i);
  }
}

}  // namespace x2car::sim::detail
