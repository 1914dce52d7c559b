// Internal to generate_world (world.cpp, world_road.cpp, world_roadside.cpp, world_traffic.cpp):
// spatial indices that keep objects off the road and off each other, and the builder that numbers
// the objects it adds.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "x2car/sim/random.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim::detail {

// A rectangle in the horizontal plane: centre, heading of its length, half sizes [m].
struct Footprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double heading = 0.0;  // [rad]
  double half_length = 0.5;
  double half_width = 0.5;

  double radius() const { return std::hypot(half_length, half_width); }
  // Its corners, edge points at most `spacing` [m] apart, and its centre.
  std::vector<Eigen::Vector2d> sample_points(double spacing) const;
};

// Whether two rectangles overlap (separating axis test).
bool overlap(const Footprint& a, const Footprint& b);

// Integer cell of a horizontal grid, hashed.
struct CellKey {
  std::int64_t x = 0, y = 0;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {
  std::size_t operator()(const CellKey& key) const {
    return std::hash<std::int64_t>()(key.x * 73856093LL ^ key.y * 19349663LL);
  }
};

// The footprints placed so far, to keep new ones from overlapping them.
class FootprintIndex {
 public:
  explicit FootprintIndex(double cell_m = 20.0) : cell_(cell_m) {}
  bool overlaps_any(const Footprint& footprint) const;
  void insert(const Footprint& footprint);

 private:
  CellKey key(double x, double y) const;
  double cell_;
  std::vector<Footprint> footprints_;
  std::unordered_map<CellKey, std::vector<std::size_t>, CellHash> cells_;
};

// The road's stations in a horizontal grid: nearest-station queries, and whether a point keeps
// clear of every stretch of road (the road may pass a point more than once, e.g. round a block).
class StationIndex {
 public:
  explicit StationIndex(const RoadLayout& road, double cell_m = 10.0);

  // The station nearest to a horizontal point (within `search_m` [m]); nullptr when none is.
  const RoadStation* nearest(const Eigen::Vector2d& point, double search_m) const;
  // Calls visit(station, section, distance [m]) for every station within `radius_m` of a point.
  template <typename Visit>
  void visit_near(const Eigen::Vector2d& point, double radius_m, Visit visit) const {
    const auto reach = static_cast<std::int64_t>(std::ceil(radius_m / cell_));
    const CellKey centre = key(point);
    for (std::int64_t x = centre.x - reach; x <= centre.x + reach; ++x) {
      for (std::int64_t y = centre.y - reach; y <= centre.y + reach; ++y) {
        const auto cell = cells_.find({x, y});
        if (cell == cells_.end()) continue;
        for (const std::size_t i : cell->second) {
          const RoadStation& station = road_.stations[i];
          const double distance = (station.centre.head<2>() - point).norm();
          if (distance <= radius_m) visit(station, road_.segment_at(station.s).section, distance);
        }
      }
    }
  }
  double max_clear_edge() const { return max_edge_; }

  // Which edge of the cross-section a point must keep beyond.
  enum class Edge { kAsphalt, kClear };
  // True when `point` is at least the edge's lateral offset (+ margin [m]) from every station's
  // centre line within reach.
  bool clear_of_road(const Eigen::Vector2d& point, Edge edge, double margin_m = 0.0) const;

 private:
  CellKey key(const Eigen::Vector2d& point) const;
  const RoadLayout& road_;
  double cell_;
  double max_edge_ = 0.0;  // the widest clear edge of any segment [m]
  std::unordered_map<CellKey, std::vector<std::size_t>, CellHash> cells_;
};

class WorldBuilder {
 public:
  WorldBuilder(World& world, const WorldOptions& options, std::uint64_t seed);

  WorldObject& add(ObjectKind kind, const Material& material,
                   const Eigen::Isometry3d& world_from_object, const Eigen::Vector3d& size);
  WorldObject& add_strip(ObjectKind kind, const Material& material, const RoadStrip& strip);

  // Places a solid standing on the ground if its footprint keeps clear of the road (beyond
  // `edge`) and of every solid placed so far; returns whether it did.
  bool try_add_solid(ObjectKind kind, const Material& material, const Footprint& footprint,
                     double base_z, double height, StationIndex::Edge edge);

  World& world;
  const WorldOptions& options;
  std::uint64_t seed;  // of the world's objects; parts derive their own streams from it
  Random random;
  StationIndex stations;
  FootprintIndex footprints;
};

// Pose of a footprint standing upright with its base at base_z [m].
Eigen::Isometry3d upright_pose(const Footprint& footprint, double base_z);

// The parts of generate_world, in the order it calls them.
void add_road_surfaces(WorldBuilder& builder, const Route& route);
void add_roadside(WorldBuilder& builder, const Route& route);
void add_traffic(WorldBuilder& builder, std::span<const VehicleState> ego);

// A car body's material: one of the common paints with its reflectivity at 905 nm (white 0.7,
// black 0.05).
Material car_material(double rcs_dbsm, Random& random);

// A material varied around the standard one: colour from `colours`, reflectivity scaled by
// [1 - spread, 1 + spread], RCS as given.
Material varied_material(Surface surface, std::span<const std::uint32_t> colours, double spread,
                         double rcs_dbsm, Random& random);

}  // namespace x2car::sim::detail
