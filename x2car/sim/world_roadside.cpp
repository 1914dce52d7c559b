// generate_world, part 2: what stands beside the road: stop signs and other traffic signs, street
// lights, trees, buildings and parked cars. Each kind draws from its own random stream; every
// solid keeps clear of the road (all of it: the road may pass a place twice) and of the solids
// placed before it.
#include <algorithm>
#include <array>
#include <cmath>

#include "x2car/sim/world_builder.hpp"

namespace x2car::sim::detail {
namespace {

using Edge = StationIndex::Edge;

constexpr std::array<std::uint32_t, 6> kFacadeColours = {0xc8b89a, 0xe0d8c8, 0x9a6a4a,
                                                         0xb0b4b8, 0xd8c090, 0x7a7f88};
constexpr std::array<std::uint32_t, 4> kSignColours = {0xd02020, 0x2050c0, 0xf0f0f0, 0xf0c000};

// Stretches where the road turns or the car stops: no buildings or parked cars there, as the
// cross streets of an intersection would be (they are not modelled).
class BusyStretches {
 public:
  BusyStretches(const RoadLayout& road, const Route& route, double gap) {
    if (gap <= 0.0) return;
    for (const RoadStation& station : road.stations) {
      if (std::abs(station.curvature) > 1.0 / 60.0) add(station.s - gap, station.s + gap);
    }
    for (const double stop : route.stop_points()) add(stop - 0.5 * gap, stop + 1.5 * gap);
  }
  bool overlaps(double a, double b) const {
    return std::any_of(stretches_.begin(), stretches_.end(),
                       [&](const auto& busy) { return a < busy.second && b > busy.first; });
  }

 private:
  void add(double a, double b) {
    if (!stretches_.empty() && a <= stretches_.back().second) {
      stretches_.back().second = std::max(stretches_.back().second, b);
    } else {
      stretches_.push_back({a, b});
    }
  }
  std::vector<std::pair<double, double>> stretches_;
};

// A footprint at road coordinates (s, lateral), its length along the road.
Footprint footprint_at(const RoadStation& station, double lateral, double length, double width) {
  Footprint footprint;
  footprint.centre = station.surface_point(lateral).head<2>();
  footprint.heading = station.heading_enu();
  footprint.half_length = 0.5 * length;
  footprint.half_width = 0.5 * width;
  return footprint;
}

// Ground height beside the road at a station: the sidewalk (urban) or the shoulder's edge [m].
double roadside_ground(const WorldBuilder& builder, const RoadStation& station, double side) {
  const CrossSection& section = builder.world.road.segment_at(station.s).section;
  return station.surface_point(side * section.sidewalk_edge, section.roadside_height).z();
}

// Calls place(s, side) every `spacing` [m] (jittered by +-30 %) along each side, from a random
// start; the segments of `kind` only.
template <typename Place>
void along_both_sides(WorldBuilder& builder, Random& rng, Scenario kind, double spacing,
                      Place place) {
  if (spacing <= 0.0) return;
  const RoadLayout& road = builder.world.road;
  for (const double side : {-1.0, 1.0}) {
    for (double s = road.s_begin() + rng.uniform(0.0, spacing); s < road.s_end();
         s += spacing * rng.uniform(0.7, 1.3)) {
      if (road.segment_at(s).section.kind == kind) place(s, side);
    }
  }
}

// A sign: post and plate; x of its frame is the way the plate faces (towards the traffic it is
// for), size = (plate thickness, plate width, height of the plate's top).
void add_sign(WorldBuilder& builder, Random& rng, double s, double side, double plate_m,
              double top_m, std::uint32_t colour) {
  const RoadStation station = builder.world.road.station_at(s);
  const CrossSection& section = builder.world.road.segment_at(s).section;
  const double lateral = side * (section.kind == Scenario::kUrban ? section.asphalt_edge + 0.15
                                                                  : section.guard_rail + 1.0) +
                         side * 0.5 * plate_m;
  Footprint footprint = footprint_at(station, lateral, 0.1, plate_m);
  if (side < 0.0) footprint.heading += kPi;  // right side: faces the car coming along s
  Material face = standard_material(Surface::kSignFace);
  face.colour_rgb = colour;
  face.radar_cross_section_dbsm = rng.uniform(5.0, 15.0);
  builder.try_add_solid(ObjectKind::kTrafficSign, face, footprint,
                        roadside_ground(builder, station, side), top_m, Edge::kAsphalt);
}

void add_stop_signs(WorldBuilder& builder, const Route& route) {
  Random rng(Random::derive_seed(builder.seed, 11));
  for (const double stop : route.stop_points()) {
    if (builder.world.road.segment_at(stop).section.kind != Scenario::kUrban) continue;
    add_sign(builder, rng, stop + 5.5, -1.0, 0.75, 2.6, 0xd02020);
  }
}

void add_signs(WorldBuilder& builder) {
  Random rng(Random::derive_seed(builder.seed, 12));
  const double spacing = builder.options.roadside.sign_spacing_m;
  auto place = [&](double s, double side) {
    const bool highway = builder.world.road.segment_at(s).section.kind == Scenario::kHighway;
    const double plate = highway ? rng.uniform(1.5, 2.5) : rng.uniform(0.6, 0.9);
    const double top = highway ? rng.uniform(3.5, 4.5) : rng.uniform(2.4, 3.0);
    const auto colour =
        kSignColours[static_cast<std::size_t>(rng.uniform01() * kSignColours.size())];
    add_sign(builder, rng, s, side, plate, top, colour);
  };
  along_both_sides(builder, rng, Scenario::kUrban, spacing, place);
  along_both_sides(builder, rng, Scenario::kHighway, 5.0 * spacing, place);
}

void add_poles(WorldBuilder& builder) {
  Random rng(Random::derive_seed(builder.seed, 13));
  const double spacing = builder.options.roadside.pole_spacing_m;
  auto place = [&](double s, double side) {
    const RoadStation station = builder.world.road.station_at(s);
    const CrossSection& section = builder.world.road.segment_at(s).section;
    const bool urban = section.kind == Scenario::kUrban;
    const double lateral = side * (urban ? section.asphalt_edge + 0.5 : section.guard_rail + 2.0);
    const double diameter = rng.uniform(0.15, 0.25);
    Material metal = standard_material(Surface::kMetal);
    metal.radar_cross_section_dbsm = rng.uniform(0.0, 10.0);
    builder.try_add_solid(
        ObjectKind::kPole, metal, footprint_at(station, lateral, diameter, diameter),
        roadside_ground(builder, station, side), rng.uniform(6.0, 10.0), Edge::kAsphalt);
  };
  // Street lights alternate sides in town: each side gets every other one.
  along_both_sides(builder, rng, Scenario::kUrban, 2.0 * spacing, place);
  along_both_sides(builder, rng, Scenario::kHighway, 4.0 * spacing, place);
}

// Trees: size = crown diameter (x, y) and total height; the crown is the main material.
void add_trees(WorldBuilder& builder) {
  Random rng(Random::derive_seed(builder.seed, 14));
  const double spacing = builder.options.roadside.tree_spacing_m;
  auto place = [&](double s, double side) {
    const RoadStation station = builder.world.road.station_at(s);
    const CrossSection& section = builder.world.road.segment_at(s).section;
    const bool urban = section.kind == Scenario::kUrban;
    const double crown = rng.uniform(3.0, 7.0);
    const double lateral =
        side * (urban ? section.asphalt_edge + 1.1 : section.guard_rail + rng.uniform(3.0, 25.0));
    Footprint footprint = footprint_at(station, lateral, urban ? 0.6 : crown, urban ? 0.6 : crown);
    const Material foliage = varied_material(Surface::kFoliage, {}, 0.2, -5.0, rng);
    const double height = rng.uniform(5.0, 12.0);
    if (builder.try_add_solid(ObjectKind::kTree, foliage, footprint,
                              roadside_ground(builder, station, side), height, Edge::kAsphalt)) {
      builder.world.objects.back().size.head<2>().setConstant(crown);
    }
  };
  along_both_sides(builder, rng, Scenario::kUrban, spacing, place);
  along_both_sides(builder, rng, Scenario::kHighway, 0.5 * spacing, place);
}

void add_buildings(WorldBuilder& builder, const BusyStretches& busy) {
  Random rng(Random::derive_seed(builder.seed, 15));
  const RoadsideOptions& o = builder.options.roadside;
  const RoadLayout& road = builder.world.road;
  for (const double side : {-1.0, 1.0}) {
    for (double s = road.s_begin(); s < road.s_end();) {
      const double length = rng.uniform(o.building_min_length_m, o.building_max_length_m);
      const double depth = rng.uniform(o.building_min_depth_m, o.building_max_depth_m);
      const double height = rng.uniform(o.building_min_height_m, o.building_max_height_m);
      const double setback = rng.uniform(0.5, o.building_max_setback_m);
      const bool built = rng.uniform01() < o.building_frontage;
      const CrossSection& section = road.segment_at(s + 0.5 * length).section;
      if (built && section.kind == Scenario::kUrban && !busy.overlaps(s, s + length)) {
        const RoadStation station = road.station_at(s + 0.5 * length);
        const double lateral = side * (section.clear_edge + setback + 0.5 * depth);
        const Material facade =
            varied_material(Surface::kFacade, kFacadeColours, 0.3, rng.uniform(20.0, 30.0), rng);
        builder.try_add_solid(ObjectKind::kBuilding, facade,
                              footprint_at(station, lateral, length, depth),
                              roadside_ground(builder, station, side), height, Edge::kClear);
      }
      s += length + rng.uniform(0.0, o.building_max_gap_m);
    }
  }
}

// Parked cars in the left-hand parking lane, facing against s (parked with the traffic of that
// side), on the road surface.
void add_parked_cars(WorldBuilder& builder, const BusyStretches& busy) {
  Random rng(Random::derive_seed(builder.seed, 16));
  const RoadsideOptions& o = builder.options.roadside;
  const RoadLayout& road = builder.world.road;
  if (o.parked_car_spacing_m <= 0.0) return;
  for (double s = road.s_begin() + 0.5 * o.parked_car_spacing_m; s < road.s_end();
       s += o.parked_car_spacing_m) {
    const CrossSection& section = road.segment_at(s).section;
    const bool taken = rng.uniform01() < o.parked_car_share;
    const double length = rng.uniform(4.0, 5.0);
    const double width = rng.uniform(1.75, 1.9);
    const double height = rng.uniform(1.4, 1.6);
    const Material paint = car_material(rng.uniform(8.0, 15.0), rng);
    if (!taken || section.kind != Scenario::kUrban || busy.overlaps(s - 3.0, s + 3.0)) continue;
    const RoadStation station = road.station_at(s);
    const double lateral = 0.5 * (section.edge_line + section.asphalt_edge);
    const Footprint footprint = footprint_at(station, lateral, length, width);
    if (builder.footprints.overlaps_any(footprint)) continue;
    builder.footprints.insert(footprint);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = station.surface_rotation() *
                    Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = station.surface_point(lateral);
    builder.add(ObjectKind::kParkedCar, paint, pose, {length, width, height});
  }
}

}  // namespace

void add_roadside(WorldBuilder& builder, const Route& route) {
  const BusyStretches busy(builder.world.road, route, builder.options.roadside.intersection_gap_m);
  add_stop_signs(builder, route);
  add_poles(builder);
  add_signs(builder);
  add_trees(builder);
  add_buildings(builder, busy);
  add_parked_cars(builder, busy);
}

}  // namespace x2car::sim::detail
