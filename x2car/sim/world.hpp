// The simulator's 3-D world (DESIGN §4): a procedural road scene laid out along the route, seen
// by every simulated sensor. This is a plain layout, independent of any ray tracer: the LiDAR
// traces its triangle meshes (world_mesh.hpp, world_scene.hpp), the radar turns its objects into
// reflectors, the camera renders its materials.
//
// What is in it: the road surface (following the route's grade and crossfall; the car's wheels are
// on it), painted lane markings and stop lines, curbs and sidewalks (urban), hard shoulders and
// guard rails on posts (highway), the terrain around the road, buildings set back from the
// sidewalk, street lights and other poles, traffic signs (a stop sign at every stop line), trees,
// parked cars (urban, in the left-hand parking lane), and moving cars and cyclists on paths along
// the road (oncoming cars, cyclists in the right-hand bike lane, highway traffic in both
// carriageways), each with its pose as a function of time.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "x2car/sim/road_layout.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

enum class ObjectKind : std::uint8_t {
  kRoad,           // asphalt, shoulders included
  kLaneMarking,    // painted lines and stop lines
  kCurb,           // the curb's vertical face
  kSidewalk,       // the sidewalk's top
  kTerrain,        // ground beside the road
  kGuardRail,      // the rail's band
  kGuardRailPost,  // its posts
  kBuilding,
  kPole,         // street lights
  kTrafficSign,  // post and plate
  kTree,         // trunk and crown
  kParkedCar,
  kCar,      // moving
  kCyclist,  // moving
};

std::string_view to_string(ObjectKind kind);  // "road", "lane_marking", ...

// What a surface is made of: the camera's texture key.
enum class Surface : std::uint8_t {
  kAsphalt,
  kLanePaint,
  kConcrete,  // curbs
  kPaving,    // sidewalks
  kGrass,
  kFacade,
  kMetal,     // poles, posts, guard rails
  kSignFace,  // retro-reflective sheeting
  kBark,
  kFoliage,
  kCarPaint,
  kGlass,
  kTyre,
  kClothing,
};

struct Material {
  Surface surface = Surface::kAsphalt;
  std::uint32_t colour_rgb = 0x808080;  // base colour 0xRRGGBB (camera)
  // Diffuse reflectance at 905 nm, 0..1; retro-reflectors exceed 1 (they return more than a white
  // Lambertian surface).
  double lidar_reflectivity = 0.1;
  double radar_cross_section_dbsm = -20.0;  // of the whole object, seen from the side [dBsm]
};

// The typical material of a surface; objects vary colour, reflectivity and RCS around it.
Material standard_material(Surface surface);

// The shape of a road-following object, in road coordinates (road_layout.hpp). A flat strip has
// height_bottom == height_top; a vertical band (curb face, guard rail) has lateral_min ==
// lateral_max. The terrain is a height field instead (world_mesh.hpp): its strip gives its extent.
struct RoadStrip {
  double s_begin = 0.0;        // along the route [m]
  double s_end = 0.0;          // [m]
  double lateral_min = 0.0;    // from the centre line, left positive [m]
  double lateral_max = 0.0;    // [m]
  double height_bottom = 0.0;  // above the road surface [m]
  double height_top = 0.0;     // [m]
};

struct WorldObject {
  std::uint32_t id = 0;  // its index in World::objects
  ObjectKind kind = ObjectKind::kBuilding;
  // Object frame: origin at the centre of its footprint on the ground, x along its length (a car's
  // forward; a sign's x is the way its plate faces), z up (parked cars: the road's normal). For
  // strips: the road's frame at the strip's middle, on the strip.
  Eigen::Isometry3d world_from_object = Eigen::Isometry3d::Identity();
  // Length (x), width (y), height (z) [m]. Trees: crown diameter, crown diameter, total height;
  // signs: post, plate width, height of the plate's top; strips: length along s, width, height.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Material material;  // of its main surface (multi-part objects: world_mesh.hpp names the others)
  std::optional<RoadStrip> strip;  // road-following objects: their exact shape
};

// A car or cyclist driving along the road at a constant speed, at a fixed lateral offset.
struct MovingObject {
  std::uint32_t id = 0;  // World::objects.size() + its index in World::movers
  ObjectKind kind = ObjectKind::kCar;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // length, width, height [m]
  Material material;
  double lateral = 0.0;    // of its path from the centre line, left positive [m]
  double s_at_zero = 0.0;  // its position along the road at time 0 [m]
  // Rate of s [m/s]: > 0 the route's way, < 0 against it (oncoming). Its true speed differs by
  // the curve's lateral factor, 1 - curvature x (its offset from the route).
  double speed = 0.0;
  double s_min = 0.0;  // the stretch of road it drives on (one kind of road) [m]
  double s_max = 0.0;  // [m]
};

struct World {
  RoadLayout road;
  std::vector<WorldObject> objects;
  std::vector<MovingObject> movers;

  // Whether the mover is on its stretch of road at `time` [s]: s_at_zero + speed * time within
  // [s_min, s_max].
  bool mover_present(const MovingObject& mover, double time) const;
  // world_from_object of the mover at `time` [s]: on the road surface, facing its way of travel.
  // Clamped to the road's ends when it is not present.
  Eigen::Isometry3d mover_pose(const MovingObject& mover, double time) const;
  // Its velocity in ENU [m/s].
  Eigen::Vector3d mover_velocity(const MovingObject& mover, double time) const;

  // The kind of an object or mover by id; throws std::out_of_range for an unknown id.
  ObjectKind kind_of(std::uint32_t id) const;
};

// Spacings are mean distances between objects along one side of the road [m]; 0 turns a kind off.
struct RoadsideOptions {
  // Buildings (urban): rows along both sides, set back from the sidewalk.
  double building_min_length_m = 8.0;   // along the road [m]
  double building_max_length_m = 30.0;  // [m]
  double building_min_depth_m = 8.0;    // [m]
  double building_max_depth_m = 20.0;   // [m]
  double building_min_height_m = 5.0;   // [m]
  double building_max_height_m = 25.0;  // [m]
  double building_max_setback_m = 6.0;  // beyond the sidewalk, drawn in [0.5, max] [m]
  double building_max_gap_m = 12.0;     // between neighbours, drawn in [0, max] [m]
  double building_frontage = 0.85;      // share of the frontage that is built on, [0, 1]
  double intersection_gap_m = 20.0;     // no buildings this close to turns and stop lines [m]
  // Street furniture.
  double pole_spacing_m = 35.0;            // street lights, alternating sides (urban) [m]
  double sign_spacing_m = 80.0;            // traffic signs besides the stop signs [m]
  double tree_spacing_m = 18.0;            // urban: on the sidewalk; highway: beyond the rails [m]
  double parked_car_spacing_m = 9.0;       // urban: parking slots on the left; 0 for none [m]
  double parked_car_share = 0.5;           // share of slots taken, [0, 1]
  double guard_rail_post_spacing_m = 4.0;  // highway [m]
  double terrain_half_width_m = 60.0;      // terrain this far from the centre line [m]
  double terrain_cell_m = 2.0;             // terrain grid spacing [m]

  void Check() const;
};

struct TrafficOptions {
  // Urban densities give a radar about a third of its detections on moving objects (issue 6 asks
  // for >= 30 %): 34-39 % on 60 s urban drives, seeds 1-5 (10 and 4 per km gave 7-16 %). That is
  // busy town traffic: 50 cars per km at 40 km/h is ~2000 cars an hour.
  double oncoming_cars_per_km = 50.0;          // urban, in the opposite lane
  double cyclists_per_km = 12.0;               // urban, in the right-hand bike lane, riding our way
  double highway_cars_per_km_lane = 6.0;       // per lane of each highway carriageway
  double urban_min_speed_mps = 25.0 / 3.6;     // cars [m/s]
  double urban_max_speed_mps = 50.0 / 3.6;     // [m/s]
  double highway_min_speed_mps = 80.0 / 3.6;   // [m/s]
  double highway_max_speed_mps = 130.0 / 3.6;  // [m/s]
  double cyclist_min_speed_mps = 3.0;          // [m/s]
  double cyclist_max_speed_mps = 7.0;          // [m/s]
  // Movers keep at least this gap [m] to the car's own position whenever they share its lane
  // (paths that would run into it are not used).
  double ego_clearance_m = 12.0;

  void Check() const;
};

struct WorldOptions {
  RoadOptions road;
  RoadsideOptions roadside;
  TrafficOptions traffic;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// A world along `route` for the scenario (the road kind where the route has no sections). `ego`
// is the car's drive (may be empty): moving objects are kept clear of it, and they drive for its
// duration. The same arguments give the same world on every platform (all draws through
// sim::Random). Throws std::invalid_argument on bad options.
World generate_world(const Route& route, Scenario scenario, std::span<const VehicleState> ego,
                     const WorldOptions& options, std::uint64_t seed);

}  // namespace x2car::sim
