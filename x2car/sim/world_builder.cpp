#include "x2car/sim/world_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace x2car::sim::detail {
namespace {

Eigen::Vector2d horizontal(const Eigen::Vector3d& point) { return point.head<2>(); }

// Half the extent of a footprint projected on a unit axis.
double projected_radius(const Footprint& footprint, const Eigen::Vector2d& axis) {
  const Eigen::Vector2d along(std::cos(footprint.heading), std::sin(footprint.heading));
  const Eigen::Vector2d across(-along.y(), along.x());
  return footprint.half_length * std::abs(along.dot(axis)) +
         footprint.half_width * std::abs(across.dot(axis));
}

}  // namespace

std::vector<Eigen::Vector2d> Footprint::sample_points(double spacing) const {
  const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
  const Eigen::Vector2d across(-along.y(), along.x());
  std::vector<Eigen::Vector2d> points = {centre};
  const int steps_l = std::max(1, static_cast<int>(std::ceil(2.0 * half_length / spacing)));
  const int steps_w = std::max(1, static_cast<int>(std::ceil(2.0 * half_width / spacing)));
  for (int i = 0; i <= steps_l; ++i) {
    const double l = -half_length + 2.0 * half_length * i / steps_l;
    points.push_back(centre + l * along + half_width * across);
    points.push_back(centre + l * along - half_width * across);
  }
  for (int j = 1; j < steps_w; ++j) {
    const double w = -half_width + 2.0 * half_width * j / steps_w;
    points.push_back(centre + half_length * along + w * across);
    points.push_back(centre - half_length * along + w * across);
  }
  return points;
}

bool overlap(const Footprint& a, const Footprint& b) {
  const Eigen::Vector2d offset = b.centre - a.centre;
  if (offset.norm() > a.radius() + b.radius()) return false;
  for (const Footprint* f : {&a, &b}) {
    const Eigen::Vector2d along(std::cos(f->heading), std::sin(f->heading));
    for (const Eigen::Vector2d& axis : {along, Eigen::Vector2d(-along.y(), along.x())}) {
      if (std::abs(offset.dot(axis)) > projected_radius(a, axis) + projected_radius(b, axis)) {
        return false;
      }
    }
  }
  return true;
}

CellKey FootprintIndex::key(double x, double y) const {
  return {static_cast<std::int64_t>(std::floor(x / cell_)),
          static_cast<std::int64_t>(std::floor(y / cell_))};
}

bool FootprintIndex::overlaps_any(const Footprint& footprint) const {
  const double r = footprint.radius();
  const CellKey low = key(footprint.centre.x() - r, footprint.centre.y() - r);
  const CellKey high = key(footprint.centre.x() + r, footprint.centre.y() + r);
  for (std::int64_t x = low.x; x <= high.x; ++x) {
    for (std::int64_t y = low.y; y <= high.y; ++y) {
      const auto cell = cells_.find({x, y});
      if (cell == cells_.end()) continue;
      for (const std::size_t i : cell->second) {
        if (overlap(footprint, footprints_[i])) return true;
      }
    }
  }
  return false;
}

void FootprintIndex::insert(const Footprint& footprint) {
  const double r = footprint.radius();
  const CellKey low = key(footprint.centre.x() - r, footprint.centre.y() - r);
  const CellKey high = key(footprint.centre.x() + r, footprint.centre.y() + r);
  for (std::int64_t x = low.x; x <= high.x; ++x) {
    for (std::int64_t y = low.y; y <= high.y; ++y) cells_[{x, y}].push_back(footprints_.size());
  }
  footprints_.push_back(footprint);
}

StationIndex::StationIndex(const RoadLayout& road, double cell_m) : road_(road), cell_(cell_m) {
  for (std::size_t i = 0; i < road.stations.size(); ++i) {
    cells_[key(horizontal(road.stations[i].centre))].push_back(i);
  }
  for (const RoadSegment& segment : road.segments) {
    max_edge_ = std::max(max_edge_, segment.section.clear_edge);
  }
}

CellKey StationIndex::key(const Eigen::Vector2d& point) const {
  return {static_cast<std::int64_t>(std::floor(point.x() / cell_)),
          static_cast<std::int64_t>(std::floor(point.y() / cell_))};
}

const RoadStation* StationIndex::nearest(const Eigen::Vector2d& point, double search_m) const {
  const RoadStation* best = nullptr;
  double best_distance = search_m;
  const auto reach = static_cast<std::int64_t>(std::ceil(search_m / cell_));
  const CellKey centre = key(point);
  for (std::int64_t x = centre.x - reach; x <= centre.x + reach; ++x) {
    for (std::int64_t y = centre.y - reach; y <= centre.y + reach; ++y) {
      const auto cell = cells_.find({x, y});
      if (cell == cells_.end()) continue;
      for (const std::size_t i : cell->second) {
        const double distance = (horizontal(road_.stations[i].centre) - point).norm();
        if (distance < best_distance) {
          best_distance = distance;
          best = &road_.stations[i];
        }
      }
    }
  }
  return best;
}

bool StationIndex::clear_of_road(const Eigen::Vector2d& point, Edge edge, double margin_m) const {
  bool clear = true;
  visit_near(point, max_edge_ + margin_m + 1.0,
             [&](const RoadStation&, const CrossSection& section, double distance) {
               const double needed =
                   (edge == Edge::kAsphalt ? section.asphalt_edge : section.clear_edge) + margin_m;
               if (distance < needed) clear = false;
             });
  return clear;
}

WorldBuilder::WorldBuilder(World& world_, const WorldOptions& options_, std::uint64_t seed_)
    : world(world_), options(options_), seed(seed_), random(seed_), stations(world_.road) {}

WorldObject& WorldBuilder::add(ObjectKind kind, const Material& material,
                               const Eigen::Isometry3d& world_from_object,
                               const Eigen::Vector3d& size) {
  WorldObject& object = world.objects.emplace_back();
  object.id = static_cast<std::uint32_t>(world.objects.size() - 1);
  object.kind = kind;
  object.material = material;
  object.world_from_object = world_from_object;
  object.size = size;
  return object;
}

WorldObject& WorldBuilder::add_strip(ObjectKind kind, const Material& material,
                                     const RoadStrip& strip) {
  const double middle = 0.5 * (strip.s_begin + strip.s_end);
  const RoadStation station = world.road.station_at(middle);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = station.surface_rotation();
  pose.translation() =
      station.surface_point(0.5 * (strip.lateral_min + strip.lateral_max), strip.height_bottom);
  WorldObject& object = add(kind, material, pose,
                            {strip.s_end - strip.s_begin, strip.lateral_max - strip.lateral_min,
                             strip.height_top - strip.height_bottom});
  object.strip = strip;
  return object;
}

bool WorldBuilder::try_add_solid(ObjectKind kind, const Material& material,
                                 const Footprint& footprint, double base_z, double height,
                                 StationIndex::Edge edge) {
  for (const Eigen::Vector2d& point : footprint.sample_points(2.0)) {
    if (!stations.clear_of_road(point, edge)) return false;
  }
  if (footprints.overlaps_any(footprint)) return false;
  footprints.insert(footprint);
  add(kind, material, upright_pose(footprint, base_z),
      {2.0 * footprint.half_length, 2.0 * footprint.half_width, height});
  return true;
}

Eigen::Isometry3d upright_pose(const Footprint& footprint, double base_z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(footprint.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(footprint.centre.x(), footprint.centre.y(), base_z);
  return pose;
}

Material car_material(double rcs_dbsm, Random& random) {
  struct Paint {
    std::uint32_t colour;
    double reflectivity;
  };
  static constexpr std::array<Paint, 6> kPaints = {{{0xf2f2f2, 0.70},
                                                    {0x101010, 0.05},
                                                    {0xb8bcc0, 0.45},
                                                    {0x5c6066, 0.20},
                                                    {0xa01818, 0.30},
                                                    {0x1c3c78, 0.15}}};
  const Paint paint = kPaints[std::min<std::size_t>(
      kPaints.size() - 1, static_cast<std::size_t>(random.uniform01() * kPaints.size()))];
  return {Surface::kCarPaint, paint.colour, paint.reflectivity, rcs_dbsm};
}

Material varied_material(Surface surface, std::span<const std::uint32_t> colours, double spread,
                         double rcs_dbsm, Random& random) {
  Material material = standard_material(surface);
  if (!colours.empty()) {
    material.colour_rgb = colours[std::min(
        colours.size() - 1, static_cast<std::size_t>(random.uniform01() * colours.size()))];
  }
  material.lidar_reflectivity *= random.uniform(1.0 - spread, 1.0 + spread);
  material.radar_cross_section_dbsm = rcs_dbsm;
  return material;
}

}  // namespace x2car::sim::detail
