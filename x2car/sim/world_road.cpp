// generate_world, part 1: the road's own surfaces (asphalt, markings, curbs, sidewalks, guard
// rails and their posts) and the terrain around it.
#include <algorithm>
#include <cmath>

#include "x2car/sim/world_builder.hpp"

namespace x2car::sim::detail {
namespace {

constexpr double kStripPiece = 100.0;     // long strips are cut into pieces this long [m]
constexpr double kMarkingWidth = 0.15;    // painted lines [m]
constexpr double kMarkingHeight = 0.004;  // paint above the asphalt [m]
constexpr double kStopLineWidth = 0.4;    // along the road [m]
constexpr double kStopLineAhead = 4.5;    // ahead of the stop point (the rear axle) [m]
constexpr double kUrbanDash = 3.0, kUrbanGap = 6.0;       // centre line [m]
constexpr double kHighwayDash = 6.0, kHighwayGap = 12.0;  // lane lines [m]
constexpr double kRailBottom = 0.45, kRailTop = 0.75;     // W-beam band above the road [m]
constexpr std::uint32_t kYellowPaint = 0xe8b828;          // urban centre line
constexpr double kPostSize = 0.12, kPostHeight = 0.75;    // guard-rail posts [m]

// Adds a strip over [s_begin, s_end] in pieces of at most kStripPiece, leaving out the stretches
// where `skip(s)` holds at a piece's middle.
template <typename Skip>
void add_pieces(WorldBuilder& builder, ObjectKind kind, const Material& material, RoadStrip strip,
                double s_begin, double s_end, Skip skip) {
  const int pieces = std::max(1, static_cast<int>(std::ceil((s_end - s_begin) / kStripPiece)));
  for (int i = 0; i < pieces; ++i) {
    strip.s_begin = s_begin + (s_end - s_begin) * i / pieces;
    strip.s_end = s_begin + (s_end - s_begin) * (i + 1) / pieces;
    if (!skip(0.5 * (strip.s_begin + strip.s_end))) builder.add_strip(kind, material, strip);
  }
}

// A painted line centred `lateral` [m] from the centre line: solid (dash <= 0) or dashed, white
// or (`colour_rgb`, the camera's) another colour.
void add_line(WorldBuilder& builder, double lateral, double s_begin, double s_end, double dash,
              double gap,
              std::uint32_t colour_rgb = standard_material(Surface::kLanePaint).colour_rgb) {
  Material paint = standard_material(Surface::kLanePaint);
  paint.colour_rgb = colour_rgb;
  const RoadLayout& road = builder.world.road;
  auto in_transition = [&](double s) { return road.in_section_transition(s); };
  RoadStrip strip{0.0,
                  0.0,
                  lateral - 0.5 * kMarkingWidth,
                  lateral + 0.5 * kMarkingWidth,
                  kMarkingHeight,
                  kMarkingHeight};
  if (dash <= 0.0) {
    add_pieces(builder, ObjectKind::kLaneMarking, paint, strip, s_begin, s_end, in_transition);
    return;
  }
  for (double s = s_begin; s + dash <= s_end; s += dash + gap) {
    strip.s_begin = s;
    strip.s_end = s + dash;
    if (!in_transition(s)) builder.add_strip(ObjectKind::kLaneMarking, paint, strip);
  }
}

// A guard rail at `lateral` [m] with its posts on the side away from the road (`behind`: +1 to
// the left, -1 to the right).
void add_guard_rail(WorldBuilder& builder, double lateral, double behind, double s_begin,
                    double s_end, bool skip_transitions) {
  const RoadLayout& road = builder.world.road;
  auto skip = [&](double s) { return skip_transitions && road.in_section_transition(s); };
  const Material steel = standard_material(Surface::kMetal);
  add_pieces(builder, ObjectKind::kGuardRail,
             {steel.surface, steel.colour_rgb, steel.lidar_reflectivity * 1.3, 15.0},
             {0.0, 0.0, lateral, lateral, kRailBottom, kRailTop}, s_begin, s_end, skip);
  const double spacing = builder.options.roadside.guard_rail_post_spacing_m;
  if (spacing <= 0.0) return;
  const double post_lateral = lateral + behind * 0.5 * kPostSize;
  for (double s = s_begin + 0.5 * spacing; s < s_end; s += spacing) {
    if (skip(s)) continue;
    const RoadStation station = road.station_at(s);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() =
        Eigen::AngleAxisd(station.heading_enu(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = station.surface_point(post_lateral);
    builder.add(ObjectKind::kGuardRailPost, {Surface::kMetal, steel.colour_rgb, 0.3, 5.0}, pose,
                {kPostSize, kPostSize, kPostHeight});
  }
}

void add_urban_road(WorldBuilder& builder, const CrossSection& section, double a, double b) {
  const double curb = builder.options.road.curb_height_m;
  auto never = [](double) { return false; };
  add_pieces(builder, ObjectKind::kRoad, standard_material(Surface::kAsphalt),
             {0.0, 0.0, -section.asphalt_edge, section.asphalt_edge, 0.0, 0.0}, a, b, never);
  for (const double side : {-1.0, 1.0}) {
    add_pieces(builder, ObjectKind::kCurb, standard_material(Surface::kConcrete),
               {0.0, 0.0, side * section.asphalt_edge, side * section.asphalt_edge, 0.0, curb}, a,
               b, never);
    add_pieces(builder, ObjectKind::kSidewalk, standard_material(Surface::kPaving),
               {0.0, 0.0, std::min(side * section.asphalt_edge, side * section.sidewalk_edge),
                std::max(side * section.asphalt_edge, side * section.sidewalk_edge), curb, curb},
               a, b, never);
    add_line(builder, side * (section.edge_line - 0.5 * kMarkingWidth), a, b, 0.0, 0.0);
  }
  // The centre line between the two directions is yellow (as in North America): the camera sees
  // which line is which; its LiDAR reflectivity is the white paint's.
  add_line(builder, 0.0, a, b, kUrbanDash, kUrbanGap, kYellowPaint);
}

void add_highway_road(WorldBuilder& builder, const CrossSection& section, double a, double b) {
  auto never = [](double) { return false; };
  add_pieces(builder, ObjectKind::kRoad, standard_material(Surface::kAsphalt),
             {0.0, 0.0, -section.asphalt_edge, section.asphalt_edge, 0.0, 0.0}, a, b, never);
  for (const double side : {-1.0, 1.0}) {
    add_line(builder, side * (section.inner_edge + 0.5 * kMarkingWidth), a, b, 0.0, 0.0);
    add_line(builder, side * (section.edge_line - 0.5 * kMarkingWidth), a, b, 0.0, 0.0);
    for (int k = 1; k < section.lanes; ++k) {
      add_line(builder, side * (section.inner_edge + k * section.lane_width), a, b, kHighwayDash,
               kHighwayGap);
    }
    add_guard_rail(builder, side * section.guard_rail, side, a, b, false);
    add_guard_rail(builder, side * section.median_rail, -side, a, b, true);
  }
}

void add_stop_lines(WorldBuilder& builder, const Route& route) {
  const RoadLayout& road = builder.world.road;
  for (const double stop : route.stop_points()) {
    const double s = stop + kStopLineAhead;
    const CrossSection& section = road.segment_at(s).section;
    if (section.kind != Scenario::kUrban) continue;
    builder.add_strip(ObjectKind::kLaneMarking, standard_material(Surface::kLanePaint),
                      {s, s + kStopLineWidth, -section.edge_line, -section.inner_edge,
                       kMarkingHeight, kMarkingHeight});
  }
}

}  // namespace

void add_road_surfaces(WorldBuilder& builder, const Route& route) {
  const RoadLayout& road = builder.world.road;
  for (const RoadSegment& segment : road.segments) {
    const double a = std::max(segment.s_begin, road.s_begin());
    const double b = std::min(segment.s_end, road.s_end());
    if (!(b > a)) continue;
    if (segment.section.kind == Scenario::kHighway) {
      add_highway_road(builder, segment.section, a, b);
    } else {
      add_urban_road(builder, segment.section, a, b);
    }
  }
  add_stop_lines(builder, route);
  const RoadsideOptions& roadside = builder.options.roadside;
  if (roadside.terrain_half_width_m > 0.0) {
    // One object, laid out as a height field by world_mesh.cpp; size.x is its grid spacing.
    WorldObject& terrain =
        builder.add_strip(ObjectKind::kTerrain, standard_material(Surface::kGrass),
                          {road.s_begin(), road.s_end(), -roadside.terrain_half_width_m,
                           roadside.terrain_half_width_m, 0.0, 0.0});
    terrain.size.x() = roadside.terrain_cell_m;
  }
}

}  // namespace x2car::sim::detail
