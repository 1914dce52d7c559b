#include "x2car/sim/road_layout.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"

namespace x2car::sim {
namespace {

Scenario road_kind_of(Scenario kind) {
  return kind == Scenario::kHighway ? Scenario::kHighway : Scenario::kUrban;
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// A lane change of the route with the route point where it begins, so that its sideways shift is
// measured exactly: (p(s) - p(begin)) . left(begin).
struct MeasuredLaneChange {
  LaneChange change;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  // route point at change.s_begin (plan) [m]
  Eigen::Vector2d left = Eigen::Vector2d::UnitY();  // horizontal normal there
  double shift = 0.0;                               // the whole change's sideways shift [m]

  double shift_at(const Route& route, double s) const {
    if (s >= change.s_end) return shift;
    const RoutePoint p = route.at(s);
    return (Eigen::Vector2d(p.x, p.y) - start).dot(left);
  }
};

// Where the route runs across the road: the car's lane, its lane changes and the moves between
// the urban and the highway lane of a mixed drive.
class RouteOffsets {
 public:
  RouteOffsets(const Route& route, const std::vector<RoadSegment>& segments,
               const RoadOptions& options, Random& rng)
      : route_(route), segments_(segments), options_(options) {
    for (const LaneChange& change : route.lane_changes()) {
      const RoutePoint p = route.at(change.s_begin);
      MeasuredLaneChange measured{
          change, {p.x, p.y}, {-std::sin(p.heading_enu), std::cos(p.heading_enu)}};
      measured.shift = measured.shift_at(route, std::nextafter(change.s_end, 0.0));
      changes_.push_back(measured);
    }
    for (const RoadSegment& segment : segments_) {
      start_lanes_.push_back(
          segment.section.kind == Scenario::kHighway ? pick_start_lane(segment, rng) : 0);
    }
  }

  // The route's offset from the centre line at s in [0, length] [m].
  double at(double s) const {
    const std::size_t i = segment_index(s);
    const CrossSection& section = segments_[i].section;
    const double urban = cross_section(Scenario::kUrban, options_).right_lane_centre(0);
    if (section.kind != Scenario::kHighway) return urban;
    const double lane = highway_offset(i, s);
    // Blend into the urban lane near a neighbouring urban segment (mixed drives).
    double weight = 1.0;
    const double transition = options_.section_transition_m;
    if (i > 0 && segments_[i - 1].section.kind != Scenario::kHighway) {
      weight = std::min(weight, smoothstep((s - segments_[i].s_begin) / transition));
    }
    if (i + 1 < segments_.size() && segments_[i + 1].section.kind != Scenario::kHighway) {
      weight = std::min(weight, smoothstep((segments_[i].s_end - s) / transition));
    }
    return urban + (lane - urban) * weight;
  }

 private:
  std::size_t segment_index(double s) const {
    std::size_t i = 0;
    while (i + 1 < segments_.size() && s >= segments_[i + 1].s_begin) ++i;
    return i;
  }

  bool in_segment(const LaneChange& change, const RoadSegment& segment) const {
    return change.s_begin >= segment.s_begin && change.s_begin < segment.s_end;
  }

  // A start lane that keeps every lane change of the segment within the carriageway.
  int pick_start_lane(const RoadSegment& segment, Random& rng) const {
    int sum = 0, lowest = 0, highest = 0;
    for (const auto& measured : changes_) {
      if (!in_segment(measured.change, segment)) continue;
      sum += measured.change.lateral_offset > 0.0 ? 1 : -1;
      lowest = std::min(lowest, sum);
      highest = std::max(highest, sum);
    }
    const int first = -lowest;
    const int last = std::max(first, segment.section.lanes - 1 - highest);
    return first + static_cast<int>(rng.uniform01() * (last - first + 1));
  }

  double highway_offset(std::size_t segment, double s) const {
    const RoadSegment& road = segments_[segment];
    double offset = road.section.right_lane_centre(start_lanes_[segment]);
    for (const auto& measured : changes_) {
      if (!in_segment(measured.change, road) || measured.change.s_begin >= s) continue;
      offset += measured.shift_at(route_, s);
    }
    return offset;
  }

  const Route& route_;
  const std::vector<RoadSegment>& segments_;
  const RoadOptions& options_;
  std::vector<MeasuredLaneChange> changes_;
  std::vector<int> start_lanes_;
};

std::vector<RoadSegment> road_segments(const Route& route, Scenario scenario,
                                       const RoadOptions& options) {
  std::vector<RoadSegment> segments;
  for (const RouteSection& section : route.sections()) {
    segments.push_back(
        {section.s_begin, section.s_end, cross_section(road_kind_of(section.road_kind), options)});
  }
  if (segments.empty()) {
    segments.push_back({0.0, route.length(), cross_section(road_kind_of(scenario), options)});
  }
  segments.front().s_begin = -options.extension_m;
  segments.back().s_end = route.length() + options.extension_m;
  return segments;
}

// Station spacing at s: at most max_station_step_m, and at most max_station_turn of heading.
double station_step(const Route& route, double s, const RoadOptions& options) {
  if (s < 0.0 || s >= route.length()) return options.max_station_step_m;
  const double curvature =
      route.max_abs_curvature(s, std::min(route.length(), s + options.max_station_step_m));
  return std::clamp(options.max_station_turn / std::max(curvature, 1e-9), 0.05,
                    options.max_station_step_m);
}

RoadStation make_station(const Route& route, double s, const RouteOffsets& offsets) {
  const double clamped = std::clamp(s, 0.0, route.length());
  const RoutePoint p = route.at(clamped);
  RoadStation station;
  station.s = s;
  station.forward = {std::cos(p.heading_enu), std::sin(p.heading_enu), 0.0};
  station.left = {-station.forward.y(), station.forward.x(), 0.0};
  station.grade = p.grade;
  station.crossfall = p.crossfall;
  station.curvature = s == clamped ? p.curvature : 0.0;
  station.route_offset = offsets.at(clamped);
  const double beyond = s - clamped;  // the straight continuation beyond an end [m]
  const Eigen::Vector3d route_point =
      Eigen::Vector3d(p.x, p.y, p.z) +
      beyond * (station.forward + p.grade * Eigen::Vector3d::UnitZ());
  station.centre =
      route_point - station.route_offset * (station.left + p.crossfall * Eigen::Vector3d::UnitZ());
  return station;
}

}  // namespace

void RoadOptions::Check() const {
  const OptionsCheck check("RoadOptions");
  check.positive("lane_width_m", lane_width_m);
  check.in_range("highway_lanes", highway_lanes, 1, kMaxHighwayLanes);
  check.positive("urban_shoulder_m", urban_shoulder_m);
  check.positive("sidewalk_width_m", sidewalk_width_m);
  check.positive("curb_height_m", curb_height_m);
  check.positive("highway_median_m", highway_median_m);
  check.positive("highway_shoulder_m", highway_shoulder_m);
  check.positive("guard_rail_offset_m", guard_rail_offset_m);
  check.in_range("extension_m", extension_m, 0.0, 1000.0);
  // Stations are at least 0.05 m apart in curves (station_step); a smaller maximum would only
  // multiply the road's stations (and its meshes) for nothing.
  check.in_range("max_station_step_m", max_station_step_m, 0.05, 10.0);
  check.positive("max_station_turn", max_station_turn);
  check.positive("section_transition_m", section_transition_m);
}

double CrossSection::right_lane_centre(int k) const {
  return -(edge_line - lane_width * (k + 0.5));
}

CrossSection cross_section(Scenario road_kind, const RoadOptions& options) {
  CrossSection section;
  section.kind = road_kind_of(road_kind);
  section.lane_width = options.lane_width_m;
  if (section.kind == Scenario::kUrban) {
    section.lanes = 1;
    section.inner_edge = 0.0;
    section.edge_line = options.lane_width_m;
    section.asphalt_edge = section.edge_line + options.urban_shoulder_m;
    section.sidewalk_edge = section.asphalt_edge + options.sidewalk_width_m;
    section.clear_edge = section.sidewalk_edge;
    section.roadside_height = options.curb_height_m;
    return section;
  }
  section.lanes = options.highway_lanes;
  section.inner_edge = 0.5 * options.highway_median_m;
  section.edge_line = section.inner_edge + options.lane_width_m * options.highway_lanes;
  section.asphalt_edge = section.edge_line + options.highway_shoulder_m;
  section.sidewalk_edge = section.asphalt_edge;
  section.guard_rail = section.asphalt_edge + options.guard_rail_offset_m;
  section.median_rail = 0.2 * section.inner_edge;
  section.clear_edge = section.guard_rail + 1.0;
  section.roadside_height = 0.0;
  return section;
}

Eigen::Vector3d RoadStation::surface_point(double lateral, double height) const {
  return centre + lateral * (left + crossfall * Eigen::Vector3d::UnitZ()) +
         height * Eigen::Vector3d::UnitZ();
}

Eigen::Matrix3d RoadStation::surface_rotation() const {
  const Eigen::Vector3d along = (forward + grade * Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d across = left + crossfall * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d normal = along.cross(across).normalized();
  Eigen::Matrix3d rotation;
  rotation.col(0) = along;
  rotation.col(1) = normal.cross(along);
  rotation.col(2) = normal;
  return rotation;
}

double RoadStation::heading_enu() const { return std::atan2(forward.y(), forward.x()); }

RoadStation RoadLayout::station_at(double s) const {
  if (s <= stations.front().s) return stations.front();
  if (s >= stations.back().s) return stations.back();
  const auto after =
      std::upper_bound(stations.begin(), stations.end(), s,
                       [](double value, const RoadStation& st) { return value < st.s; });
  const RoadStation& a = *(after - 1);
  const RoadStation& b = *after;
  const double w = (s - a.s) / (b.s - a.s);
  RoadStation station;
  station.s = s;
  station.centre = a.centre + w * (b.centre - a.centre);
  station.forward = (a.forward + w * (b.forward - a.forward)).normalized();
  station.left = {-station.forward.y(), station.forward.x(), 0.0};
  station.grade = a.grade + w * (b.grade - a.grade);
  station.crossfall = a.crossfall + w * (b.crossfall - a.crossfall);
  station.route_offset = a.route_offset + w * (b.route_offset - a.route_offset);
  station.curvature = a.curvature + w * (b.curvature - a.curvature);
  return station;
}

bool RoadLayout::in_section_transition(double s) const {
  for (std::size_t i = 1; i < segments.size(); ++i) {
    if (segments[i].section.kind != segments[i - 1].section.kind &&
        std::abs(s - segments[i].s_begin) < section_transition_m) {
      return true;
    }
  }
  return false;
}

const RoadSegment& RoadLayout::segment_at(double s) const {
  const auto after =
      std::upper_bound(segments.begin(), segments.end(), s,
                       [](double value, const RoadSegment& seg) { return value < seg.s_begin; });
  return after == segments.begin() ? segments.front() : *(after - 1);
}

RoadLayout build_road_layout(const Route& route, Scenario scenario, const RoadOptions& options,
                             Random& rng) {
  options.Check();
  RoadLayout layout;
  layout.route_length = route.length();
  layout.section_transition_m = options.section_transition_m;
  layout.segments = road_segments(route, scenario, options);
  const RouteOffsets offsets(route, layout.segments, options, rng);

  // Breakpoints the stations must hit: the route's ends and its segments' and lane changes' ends.
  std::vector<double> breaks = {0.0, route.length(), route.length() + options.extension_m};
  for (const RoadSegment& segment : layout.segments) breaks.push_back(segment.s_begin);
  for (const LaneChange& change : route.lane_changes()) {
    breaks.push_back(change.s_begin);
    breaks.push_back(change.s_end);
  }
  std::sort(breaks.begin(), breaks.end());
  double s = -options.extension_m;
  for (const double next_break : breaks) {
    if (next_break <= s) continue;
    while (s < next_break - 1e-6) {
      layout.stations.push_back(make_station(route, s, offsets));
      s = std::min(next_break, s + station_step(route, s, options));
    }
  }
  layout.stations.push_back(make_station(route, s, offsets));
  return layout;
}

}  // namespace x2car::sim
