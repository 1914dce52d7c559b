#include "x2car/sim/world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/sim/world_builder.hpp"

namespace x2car::sim {
namespace {

// Objects placed along the road are 0 (none) or at least this far apart [m].
constexpr double kMinSpacingM = 0.5;
// Movers per kilometre of lane, at most.
constexpr double kMaxMoversPerKm = 500.0;
// Movers' speeds, at most [m/s].
constexpr double kMaxMoverSpeedMps = 100.0;

}  // namespace

constexpr std::array<EnumName<ObjectKind>, 14> kObjectKindNames{{
    {ObjectKind::kRoad, "road"},
    {ObjectKind::kLaneMarking, "lane_marking"},
    {ObjectKind::kCurb, "curb"},
    {ObjectKind::kSidewalk, "sidewalk"},
    {ObjectKind::kTerrain, "terrain"},
    {ObjectKind::kGuardRail, "guard_rail"},
    {ObjectKind::kGuardRailPost, "guard_rail_post"},
    {ObjectKind::kBuilding, "building"},
    {ObjectKind::kPole, "pole"},
    {ObjectKind::kTrafficSign, "traffic_sign"},
    {ObjectKind::kTree, "tree"},
    {ObjectKind::kParkedCar, "parked_car"},
    {ObjectKind::kCar, "car"},
    {ObjectKind::kCyclist, "cyclist"},
}};

std::string_view to_string(ObjectKind kind) { return enum_to_string(kObjectKindNames, kind); }

// Reflectivities at 905 nm from published LiDAR reflectance surveys (asphalt 0.05-0.2, white paint
// 0.5-0.7, concrete 0.3-0.4, vegetation 0.4-0.6 in the near infrared, retro-reflective sheeting
// several times a white Lambertian target); RCS at 77 GHz of the whole object.
Material standard_material(Surface surface) {
  switch (surface) {
    case Surface::kAsphalt:
      return {surface, 0x3a3a3c, 0.10, -20.0};
    case Surface::kLanePaint:
      return {surface, 0xf0f0f0, 0.60, -20.0};
    case Surface::kConcrete:
      return {surface, 0xa8a8a0, 0.35, -5.0};
    case Surface::kPaving:
      return {surface, 0x9c9488, 0.30, -20.0};
    case Surface::kGrass:
      return {surface, 0x4f7a32, 0.45, -20.0};
    case Surface::kFacade:
      return {surface, 0xc8b89a, 0.40, 20.0};
    case Surface::kMetal:
      return {surface, 0x8a8d91, 0.30, 5.0};
    case Surface::kSignFace:
      return {surface, 0xd02020, 3.00, 10.0};
    case Surface::kBark:
      return {surface, 0x5a4030, 0.30, -5.0};
    case Surface::kFoliage:
      return {surface, 0x3c6e28, 0.50, -5.0};
    case Surface::kCarPaint:
      return {surface, 0x2050a0, 0.30, 10.0};
    case Surface::kGlass:
      return {surface, 0x202830, 0.05, 10.0};
    case Surface::kTyre:
      return {surface, 0x141414, 0.05, 0.0};
    case Surface::kClothing:
      return {surface, 0x404060, 0.35, 0.0};
  }
  throw std::invalid_argument("standard_material: unknown surface");
}

void RoadsideOptions::Check() const {
  const OptionsCheck check("RoadsideOptions");
  // Buildings follow each other along the road, so their length is their spacing.
  check.at_least("building_min_length_m", building_min_length_m, 1.0);
  check.ordered("building_min_length_m", building_min_length_m, "building_max_length_m",
                building_max_length_m);
  check.positive("building_min_depth_m", building_min_depth_m);
  check.ordered("building_min_depth_m", building_min_depth_m, "building_max_depth_m",
                building_max_depth_m);
  check.positive("building_min_height_m", building_min_height_m);
  check.ordered("building_min_height_m", building_min_height_m, "building_max_height_m",
                building_max_height_m);
  check.at_least("building_max_setback_m", building_max_setback_m, 0.5);
  check.non_negative("building_max_gap_m", building_max_gap_m);
  check.probability("building_frontage", building_frontage);
  check.non_negative("intersection_gap_m", intersection_gap_m);
  // Objects placed every `spacing` along the road: a tiny spacing makes millions of them per
  // kilometre (hours of generation or bad_alloc), so a spacing is 0 (none) or at least 0.5 m.
  const std::string spacing_rule = fmt::format("must be 0 (none) or in [{:g}, inf)", kMinSpacingM);
  for (const auto& [field, spacing] :
       {std::pair{"pole_spacing_m", pole_spacing_m}, std::pair{"sign_spacing_m", sign_spacing_m},
        std::pair{"tree_spacing_m", tree_spacing_m},
        std::pair{"guard_rail_post_spacing_m", guard_rail_post_spacing_m}}) {
    check.that(std::isfinite(spacing) && (spacing == 0.0 || spacing >= kMinSpacingM), field,
               spacing_rule, spacing);
  }
  check.that(std::isfinite(parked_car_spacing_m) &&
                 (parked_car_spacing_m == 0.0 || parked_car_spacing_m >= 5.5),
             "parked_car_spacing_m", "must be 0 (none) or >= 5.5 (a car is up to 5 m long)",
             parked_car_spacing_m);
  check.probability("parked_car_share", parked_car_share);
  // The terrain is a grid of cells across this width all along the road: bounded for memory.
  check.in_range("terrain_half_width_m", terrain_half_width_m, 0.0, 500.0);
  check.in_range("terrain_cell_m", terrain_cell_m, 0.5, 20.0);
}

void TrafficOptions::Check() const {
  const OptionsCheck check("TrafficOptions");
  // Movers per kilometre of lane: busy traffic is ~100; more only exhausts memory.
  check.in_range("oncoming_cars_per_km", oncoming_cars_per_km, 0.0, kMaxMoversPerKm);
  check.in_range("cyclists_per_km", cyclists_per_km, 0.0, kMaxMoversPerKm);
  check.in_range("highway_cars_per_km_lane", highway_cars_per_km_lane, 0.0, kMaxMoversPerKm);
  // The traffic generator spreads movers over what the fastest covers in the drive, so an absurd
  // speed means absurdly many movers (and an int overflow of their count).
  check.non_negative("urban_min_speed_mps", urban_min_speed_mps);
  check.in_range("urban_max_speed_mps", urban_max_speed_mps, urban_min_speed_mps,
                 kMaxMoverSpeedMps);
  check.non_negative("highway_min_speed_mps", highway_min_speed_mps);
  check.in_range("highway_max_speed_mps", highway_max_speed_mps, highway_min_speed_mps,
                 kMaxMoverSpeedMps);
  check.non_negative("cyclist_min_speed_mps", cyclist_min_speed_mps);
  check.in_range("cyclist_max_speed_mps", cyclist_max_speed_mps, cyclist_min_speed_mps,
                 kMaxMoverSpeedMps);
  check.non_negative("ego_clearance_m", ego_clearance_m);
}

void WorldOptions::Check() const {
  road.Check();
  roadside.Check();
  traffic.Check();
}

bool World::mover_present(const MovingObject& mover, double time) const {
  const double s = mover.s_at_zero + mover.speed * time;
  return s >= mover.s_min && s <= mover.s_max;
}

Eigen::Isometry3d World::mover_pose(const MovingObject& mover, double time) const {
  const RoadStation station = road.station_at(mover.s_at_zero + mover.speed * time);
  Eigen::Matrix3d rotation = station.surface_rotation();
  if (mover.speed < 0.0) {  // facing against s: turn half way round about the surface normal
    rotation.col(0) = -rotation.col(0);
    rotation.col(1) = -rotation.col(1);
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = station.surface_point(mover.lateral);
  return pose;
}

Eigen::Vector3d World::mover_velocity(const MovingObject& mover, double time) const {
  if (!mover_present(mover, time)) return Eigen::Vector3d::Zero();
  constexpr double kStep = 0.05;  // [s] central difference; positions are linear between stations
  return (mover_pose(mover, time + kStep).translation() -
          mover_pose(mover, time - kStep).translation()) /
         (2.0 * kStep);
}

ObjectKind World::kind_of(std::uint32_t id) const {
  if (id < objects.size()) return objects[id].kind;
  return movers.at(id - objects.size()).kind;
}

World generate_world(const Route& route, Scenario scenario, std::span<const VehicleState> ego,
                     const WorldOptions& options, std::uint64_t seed) {
  options.Check();
  constexpr std::uint64_t kLaneStream = 1;
  constexpr std::uint64_t kObjectStream = 2;
  World world;
  Random lane_random(Random::derive_seed(seed, kLaneStream));
  world.road = build_road_layout(route, scenario, options.road, lane_random);
  detail::WorldBuilder builder(world, options, Random::derive_seed(seed, kObjectStream));
  detail::add_road_surfaces(builder, route);
  detail::add_roadside(builder, route);
  detail::add_traffic(builder, ego);
  return world;
}

}  // namespace x2car::sim
