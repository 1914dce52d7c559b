#include "x2car/sim/world_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "x2car/sim/world_builder.hpp"

namespace x2car::sim {
namespace {

using detail::CellHash;
using detail::CellKey;

constexpr double kMaxInsideCurvatureShare = 0.9;  // strips stop at 90 % of a curve's radius
constexpr double kBuriedDepth = 1.0;              // solids reach this far into the ground [m]
constexpr double kTerrainDepth = 0.3;             // terrain under the road, below it [m]
constexpr double kTerrainBelowEdge = 0.05;        // further out, below the roadside level [m]
constexpr double kWheelDiameter = 0.65, kWheelWidth = 0.22, kClearance = 0.2;  // cars [m]

// Appends the triangles of one object or mover, in world coordinates.
class MeshWriter {
 public:
  MeshWriter(TriangleMesh& mesh, const Eigen::Vector3d& origin, std::uint32_t id,
             const Material& main)
      : mesh_(mesh), origin_(origin), id_(id), main_(main) {}

  std::uint32_t vertex(const Eigen::Vector3d& p_world) {
    mesh_.vertices.push_back((p_world - origin_).cast<float>());
    return static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
  }

  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, Surface surface) {
    mesh_.triangles.push_back({a, b, c});
    mesh_.triangle_object.push_back(id_);
    mesh_.triangle_surface.push_back(surface);
    mesh_.triangle_reflectivity.push_back(static_cast<float>(
        surface == main_.surface ? main_.lidar_reflectivity
                                 : standard_material(surface).lidar_reflectivity));
  }

  // a b c d in order round the quad.
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, Surface surface) {
    triangle(a, b, c, surface);
    triangle(a, c, d, surface);
  }

  // The box [low, high] of the object frame `pose`; without its bottom face.
  void box(const Eigen::Isometry3d& pose, const Eigen::Vector3d& low, const Eigen::Vector3d& high,
           Surface surface) {
    std::array<std::uint32_t, 8> v{};
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner((i & 1) ? high.x() : low.x(), (i & 2) ? high.y() : low.y(),
                                   (i & 4) ? high.z() : low.z());
      v[static_cast<std::size_t>(i)] = vertex(pose * corner);
    }
    quad(v[4], v[5], v[7], v[6], surface);  // top
    quad(v[0], v[1], v[5], v[4], surface);  // y low
    quad(v[2], v[3], v[7], v[6], surface);  // y high
    quad(v[0], v[2], v[6], v[4], surface);  // x low
    quad(v[1], v[3], v[7], v[5], surface);  // x high
  }

  // An upright octagonal prism round (x, y) of the object frame, from z0 to z1, with a top.
  void prism(const Eigen::Isometry3d& pose, double x, double y, double radius, double z0, double z1,
             Surface surface) {
    constexpr int kSides = 8;
    std::array<std::uint32_t, 2 * kSides> v{};
    for (int i = 0; i < kSides; ++i) {
      const double a = 2.0 * kPi * i / kSides;
      const Eigen::Vector3d rim(x + radius * std::cos(a), y + radius * std::sin(a), 0.0);
      v[static_cast<std::size_t>(i)] = vertex(pose * (rim + Eigen::Vector3d(0, 0, z0)));
      v[static_cast<std::size_t>(i + kSides)] = vertex(pose * (rim + Eigen::Vector3d(0, 0, z1)));
    }
    for (int i = 0; i < kSides; ++i) {
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>((i + 1) % kSides);
      quad(v[a], v[b], v[b + kSides], v[a + kSides], surface);
      if (i > 0 && i + 1 < kSides) triangle(v[kSides], v[a + kSides], v[b + kSides], surface);
    }
  }

  // An icosahedron inscribed in the ellipsoid with `radii` round `centre` of the object frame.
  void ellipsoid(const Eigen::Isometry3d& pose, const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& radii, Surface surface) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    const std::array<Eigen::Vector3d, 12> unit = {Eigen::Vector3d(-1, t, 0),
                                                  {1, t, 0},
                                                  {-1, -t, 0},
                                                  {1, -t, 0},
                                                  {0, -1, t},
                                                  {0, 1, t},
                                                  {0, -1, -t},
                                                  {0, 1, -t},
                                                  {t, 0, -1},
                                                  {t, 0, 1},
                                                  {-t, 0, -1},
                                                  {-t, 0, 1}};
    static constexpr std::array<std::array<int, 3>, 20> kFaces = {
        {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
         {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}}};
    std::array<std::uint32_t, 12> v{};
    for (std::size_t i = 0; i < unit.size(); ++i) {
      v[i] = vertex(pose * (centre + unit[i].normalized().cwiseProduct(radii)));
    }
    for (const auto& f : kFaces) {
      triangle(v[static_cast<std::size_t>(f[0])], v[static_cast<std::size_t>(f[1])],
               v[static_cast<std::size_t>(f[2])], surface);
    }
  }

 private:
  TriangleMesh& mesh_;
  const Eigen::Vector3d& origin_;
  std::uint32_t id_;
  Material main_;
};

// A point of a strip, kept short of the centre of a tight curve on its inside.
Eigen::Vector3d strip_point(const RoadStation& station, double lateral, double height) {
  const double from_route = lateral - station.route_offset;
  if (station.curvature * from_route > kMaxInsideCurvatureShare) {
    lateral = station.route_offset + kMaxInsideCurvatureShare / station.curvature;
  }
  return station.surface_point(lateral, height);
}

void strip_mesh(const RoadLayout& road, const RoadStrip& strip, Surface surface, MeshWriter& out) {
  std::vector<RoadStation> stations = {road.station_at(strip.s_begin)};
  auto it = std::upper_bound(road.stations.begin(), road.stations.end(), strip.s_begin,
                             [](double s, const RoadStation& st) { return s < st.s; });
  for (; it != road.stations.end() && it->s < strip.s_end; ++it) stations.push_back(*it);
  stations.push_back(road.station_at(strip.s_end));
  const bool vertical = strip.lateral_min == strip.lateral_max;
  std::uint32_t previous_a = 0, previous_b = 0;
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const RoadStation& st = stations[i];
    const std::uint32_t a =
        out.vertex(vertical ? strip_point(st, strip.lateral_min, strip.height_bottom)
                            : strip_point(st, strip.lateral_min, strip.height_top));
    const std::uint32_t b =
        out.vertex(vertical ? strip_point(st, strip.lateral_min, strip.height_top)
                            : strip_point(st, strip.lateral_max, strip.height_top));
    if (i > 0) out.quad(previous_a, a, b, previous_b, surface);
    previous_a = a;
    previous_b = b;
  }
}

// The terrain's height [m] at a grid node (world_mesh.hpp). Within 1.5 cells of the asphalt it
// is below the road, within 1.5 cells of the sidewalk below the sidewalk, so that no terrain
// triangle (at most a cell's diagonal across) rises through either; further out it lies at the
// roadside level of the station that laid its cell out. Where stretches of road come close, the
// lowest of their demands wins.
double terrain_height(const detail::StationIndex& index, const RoadStation& local,
                      const CrossSection& local_section, const Eigen::Vector2d& node, double cell) {
  auto roadside = [&](const RoadStation& station, double edge, double height) {
    const double lateral = (node - station.centre.head<2>()).dot(station.left.head<2>());
    return station.surface_point(std::clamp(lateral, -edge, edge), height).z();
  };
  const double margin = 1.5 * cell;
  double lowest = std::numeric_limits<double>::infinity();
  index.visit_near(
      node, index.max_clear_edge() + margin,
      [&](const RoadStation& station, const CrossSection& section, double distance) {
        if (distance < section.asphalt_edge + margin) {
          lowest = std::min(lowest, roadside(station, section.asphalt_edge, -kTerrainDepth));
        } else if (distance < section.sidewalk_edge + margin) {
          lowest = std::min(lowest, roadside(station, section.sidewalk_edge,
                                             section.roadside_height - kTerrainBelowEdge));
        }
      });
  if (std::isfinite(lowest)) return lowest;
  return roadside(local, local_section.sidewalk_edge,
                  local_section.roadside_height - kTerrainBelowEdge);
}

void terrain_mesh(const World& world, const WorldObject& object, MeshWriter& out) {
  const RoadLayout& road = world.road;
  const double cell = object.size.x();
  const double half_width = object.strip->lateral_max;
  const detail::StationIndex index(road);
  // The cells round the road, each with the station that reached it first.
  std::unordered_map<CellKey, double, CellHash> cell_station;  // cell -> s
  std::vector<CellKey> cells;
  for (double s = road.s_begin(); s <= road.s_end(); s += 0.5 * cell) {
    const RoadStation station = road.station_at(s);
    for (double lateral = -half_width; lateral <= half_width; lateral += 0.5 * cell) {
      const Eigen::Vector3d p = station.surface_point(lateral);
      const CellKey key{static_cast<std::int64_t>(std::floor(p.x() / cell)),
                        static_cast<std::int64_t>(std::floor(p.y() / cell))};
      if (cell_station.emplace(key, s).second) cells.push_back(key);
    }
  }
  std::sort(cells.begin(), cells.end(),
            [](const CellKey& a, const CellKey& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  std::unordered_map<CellKey, std::uint32_t, CellHash> nodes;
  auto node = [&](std::int64_t i, std::int64_t j, const RoadStation& local) {
    const auto [it, added] = nodes.emplace(CellKey{i, j}, 0);
    if (added) {
      const Eigen::Vector2d xy(static_cast<double>(i) * cell, static_cast<double>(j) * cell);
      const double z = terrain_height(index, local, road.segment_at(local.s).section, xy, cell);
      it->second = out.vertex({xy.x(), xy.y(), z});
    }
    return it->second;
  };
  for (const CellKey& key : cells) {
    const RoadStation local = road.station_at(cell_station.at(key));
    out.quad(node(key.x, key.y, local), node(key.x + 1, key.y, local),
             node(key.x + 1, key.y + 1, local), node(key.x, key.y + 1, local), Surface::kGrass);
  }
}

void car_mesh(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, MeshWriter& out) {
  const double l = 0.5 * size.x(), w = 0.5 * size.y(), h = size.z();
  const double axle = l - 0.8;  // wheels 0.8 m in from the ends
  for (const double x : {-axle, axle}) {
    for (const double y : {-w + 0.5 * kWheelWidth, w - 0.5 * kWheelWidth}) {
      out.box(pose, {x - 0.5 * kWheelDiameter, y - 0.5 * kWheelWidth, 0.0},
              {x + 0.5 * kWheelDiameter, y + 0.5 * kWheelWidth, kWheelDiameter}, Surface::kTyre);
    }
  }
  if (size.x() > 8.0) {  // a truck: one box
    out.box(pose, {-l, -w, kWheelDiameter}, {l, w, h}, Surface::kCarPaint);
    return;
  }
  const double belt = kClearance + 0.55 * (h - kClearance);
  out.box(pose, {-l, -w, kClearance}, {l, w, belt}, Surface::kCarPaint);
  out.box(pose, {-0.55 * l, -0.9 * w, belt}, {0.45 * l, 0.9 * w, h}, Surface::kGlass);
}

void solid_mesh(const WorldObject& object, MeshWriter& out) {
  const Eigen::Isometry3d& pose = object.world_from_object;
  const Eigen::Vector3d half = 0.5 * object.size;
  const double h = object.size.z();
  switch (object.kind) {
    case ObjectKind::kBuilding:
      out.box(pose, {-half.x(), -half.y(), -kBuriedDepth}, {half.x(), half.y(), h},
              Surface::kFacade);
      return;
    case ObjectKind::kGuardRailPost:
      out.box(pose, {-half.x(), -half.y(), -kBuriedDepth}, {half.x(), half.y(), h},
              Surface::kMetal);
      return;
    case ObjectKind::kPole:
      out.prism(pose, 0.0, 0.0, half.x(), -kBuriedDepth, h, Surface::kMetal);
      return;
    case ObjectKind::kTrafficSign: {
      const double plate_height = std::min(object.size.y(), 0.75 * object.size.y() + 0.2);
      out.box(pose, {-0.04, -0.04, -kBuriedDepth}, {0.04, 0.04, h - 0.5 * plate_height},
              Surface::kMetal);
      out.box(pose, {0.04, -half.y(), h - plate_height}, {0.07, half.y(), h}, Surface::kSignFace);
      return;
    }
    case ObjectKind::kTree: {
      const double crown_radius_z = std::min(0.6 * object.size.x(), 0.35 * h);
      const double trunk = 0.1 + 0.01 * h;
      out.prism(pose, 0.0, 0.0, trunk, -kBuriedDepth, h - crown_radius_z, Surface::kBark);
      out.ellipsoid(pose, {0.0, 0.0, h - crown_radius_z}, {half.x(), half.y(), crown_radius_z},
                    Surface::kFoliage);
      return;
    }
    case ObjectKind::kParkedCar:
    case ObjectKind::kCar:
      car_mesh(pose, object.size, out);
      return;
    default:
      out.box(pose, {-half.x(), -half.y(), 0.0}, {half.x(), half.y(), h}, object.material.surface);
  }
}

}  // namespace

void append_object_mesh(const World& world, const WorldObject& object,
                        const Eigen::Vector3d& origin, TriangleMesh& mesh) {
  MeshWriter out(mesh, origin, object.id, object.material);
  if (object.kind == ObjectKind::kTerrain && object.strip) {
    terrain_mesh(world, object, out);
  } else if (object.strip) {
    strip_mesh(world.road, *object.strip, object.material.surface, out);
  } else {
    solid_mesh(object, out);
  }
}

void append_mover_mesh(const World& world, const MovingObject& mover, double time,
                       const Eigen::Vector3d& origin, TriangleMesh& mesh) {
  MeshWriter out(mesh, origin, mover.id, mover.material);
  const Eigen::Isometry3d pose = world.mover_pose(mover, time);
  if (mover.kind == ObjectKind::kCyclist) {
    const double l = 0.5 * mover.size.x(), h = mover.size.z();
    out.box(pose, {-l, -0.05, 0.0}, {l, 0.05, 0.55 * h}, Surface::kMetal);
    out.box(pose, {-0.3, -0.22, 0.5 * h}, {0.15, 0.22, h}, Surface::kClothing);
    return;
  }
  car_mesh(pose, mover.size, out);
}

TriangleMesh mesh_static_world(const World& world, const Eigen::Vector3d& origin) {
  TriangleMesh mesh;
  for (const WorldObject& object : world.objects) append_object_mesh(world, object, origin, mesh);
  return mesh;
}

}  // namespace x2car::sim
