// The road around a route (route.hpp): where its centre line runs, how wide it is and where the
// route (the car's path) lies across it. The world (world.hpp) lays its strips and objects out in
// these road coordinates: s along the route [m] and a lateral offset from the road's centre line,
// positive to the left [m].
//
// The road surface is the ruled surface the car drives on: through each route point, along the
// horizontal normal to the left, rising by the route's crossfall per metre (route.hpp), so the
// vehicle frame's origin lies on it and its z axis is the surface normal (vehicle_motion.hpp).
// Traffic drives on the right. Urban (and straight) roads have one lane each way and the car in
// the right one; highways have `highway_lanes` each way and the car in the lane the route's lane
// changes imply. Stations beyond the route's ends continue it straight, so that the car sees a road
// behind it at the start and ahead of it at the end.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "x2car/sim/random.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/scenario.hpp"

namespace x2car::sim {

struct RoadOptions {
  double lane_width_m = 3.5;        // [m]
  int highway_lanes = 3;            // per direction; the route's HighwayPlanOptions::lanes
  double urban_shoulder_m = 2.0;    // bike lane (right) or parking lane (left) beyond the edge line
  double sidewalk_width_m = 2.25;   // [m]
  double curb_height_m = 0.15;      // sidewalk above the road [m]
  double highway_median_m = 4.0;    // between the inner edge lines of the two carriageways [m]
  double highway_shoulder_m = 2.5;  // hard shoulder beyond the outer edge line [m]
  double guard_rail_offset_m = 0.5;  // guard rails this far beyond the asphalt's edge [m]
  double extension_m = 80.0;         // road continued straight beyond both route ends [m]
  double max_station_step_m = 1.0;   // station spacing along the road [m] ...
  double max_station_turn = 0.02;    // ... and at most this heading change between stations [rad]
  // Mixed drives: the car moves between the urban and the highway lane over this length [m].
  double section_transition_m = 100.0;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// One cross-section of the road, symmetric about the centre line; lateral offsets of the right
// half are the negatives of these. All [m] from the centre line.
struct CrossSection {
  Scenario kind = Scenario::kUrban;  // kUrban or kHighway
  int lanes = 1;                     // per direction
  double lane_width = 3.5;
  double inner_edge = 0.0;        // inner edge line (urban: the centre line; highway: median side)
  double edge_line = 3.5;         // outer edge line
  double asphalt_edge = 5.5;      // end of the asphalt: the curb (urban) or the shoulder's edge
  double sidewalk_edge = 7.75;    // urban: outer edge of the sidewalk; highway: = asphalt_edge
  double guard_rail = 0.0;        // highway: the outer guard rail; 0 for none
  double median_rail = 0.0;       // highway: the two median guard rails; 0 for none
  double clear_edge = 7.75;       // roadside objects stand beyond this (sidewalk objects: asphalt)
  double roadside_height = 0.15;  // the ground at sidewalk_edge above the road: the curb or 0 [m]

  // Centre of lane k of the right-hand carriageway (k = 0 the rightmost), negative [m].
  double right_lane_centre(int k) const;
};

CrossSection cross_section(Scenario road_kind, const RoadOptions& options);

struct RoadStation {
  double s = 0.0;                                      // along the route [m]
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();    // centre line on the surface, ENU [m]
  Eigen::Vector3d forward = Eigen::Vector3d::UnitX();  // horizontal unit tangent, ENU
  Eigen::Vector3d left = Eigen::Vector3d::UnitY();     // horizontal unit normal to the left
  double grade = 0.0;                                  // dz/ds, positive uphill [m/m]
  double crossfall = 0.0;                              // rise per metre to the left [m/m]
  double route_offset = 0.0;  // the route's lateral offset from the centre line, left positive [m]
  double curvature = 0.0;     // of the route's plan [1/m]

  // The point `lateral` [m] to the left of the centre line, `height` [m] above the surface.
  Eigen::Vector3d surface_point(double lateral, double height = 0.0) const;
  // x along the road (with its grade), z the surface normal, y to the left: the road's own frame.
  Eigen::Matrix3d surface_rotation() const;
  double heading_enu() const;  // of `forward` [rad]
};

// A stretch of one cross-section.
struct RoadSegment {
  double s_begin = 0.0;  // [m]
  double s_end = 0.0;    // [m]
  CrossSection section;
};

struct RoadLayout {
  std::vector<RoadStation> stations;  // s strictly increasing, from -extension to length+extension
  std::vector<RoadSegment> segments;  // consecutive, covering the stations
  double route_length = 0.0;          // [m]
  double section_transition_m = 0.0;  // RoadOptions::section_transition_m [m]

  // Linear between the stations around s (directions renormalised), clamped to the end stations.
  RoadStation station_at(double s) const;
  // The segment holding s (the first or last beyond the ends).
  const RoadSegment& segment_at(double s) const;
  // Within section_transition_m of a change between urban and highway road, where the car moves
  // between the two roads' lanes (no median rails or lane markings are laid there).
  bool in_section_transition(double s) const;
  double s_begin() const { return stations.front().s; }
  double s_end() const { return stations.back().s; }
};

// Lays the road out along `route`. `scenario` is the road kind where the route has no sections
// (kStraight roads get the urban cross-section). `rng` picks the highway lane a drive starts in
// among those its lane changes allow. Throws std::invalid_argument on bad options.
RoadLayout build_road_layout(const Route& route, Scenario scenario, const RoadOptions& options,
                             Random& rng);

}  // namespace x2car::sim
