// The named driving scenarios of `x2car simulate --scenario NAME`: how the car is driven on each
// kind of road (DrivingStyle) and the plan view of the road each scenario drives (RoadPlan).
// Everything random is drawn through sim::Random (random.hpp), so the same seed gives the same road
// on every platform.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {

// kStraight, kUrban and kHighway are also the kinds of road a route is made of; kMixed alternates
// urban and highway sections; kCity is an urban road (its section's kind is kUrban) with short
// blocks and a turn at most intersections.
enum class Scenario { kStraight, kUrban, kHighway, kMixed, kCity };

std::string to_string(Scenario scenario);  // "straight", "urban", "highway", "mixed", "city"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
Scenario scenario_from_string(std::string_view name);
std::vector<std::string> scenario_names();  // the CLI's choices, in table order

// ---- how the car is driven ------------------------------------------------------------------

// The driver's habits on one kind of road (the in-class defaults are the urban ones).
struct DrivingStyle {
  double min_speed_mps = 20.0 / 3.6;      // cruise targets are drawn uniformly in [min, max] [m/s]
  double max_speed_mps = 50.0 / 3.6;      // [m/s]
  double max_lateral_acceleration = 3.0;  // curves are taken no faster than this [m/s^2]
  double min_stretch_m = 100.0;  // one cruise target holds for a stretch of this length ... [m]
  double max_stretch_m = 300.0;  // ... to this length [m]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// Per road kind (kMixed throws: its sections are urban or highway):
//   straight  50-70 km/h,  2 m/s^2 lateral, targets change every 300-800 m (mild changes)
//   urban     20-50 km/h,  3 m/s^2 lateral, a new target per 100-300 m (city: the same)
//   highway  80-120 km/h,  2 m/s^2 lateral, a new target per 800-2000 m
DrivingStyle default_driving_style(Scenario road_kind);

// ---- the plan view of a road ----------------------------------------------------------------

// One knot of the plan curvature kappa(s), which is linear in s between knots: straights (0),
// clothoids (linear) and arcs (constant). s is the horizontal arc length [m], kappa [1/m] is
// positive turning left.
struct CurvatureKnot {
  double s = 0.0;          // [m]
  double curvature = 0.0;  // [1/m]
};

// One knot of the banking of curves: the share of the route's curve bank (VerticalProfile::
// curve_bank) at s, in [-1, 1], positive raising the left edge. Linear in s between knots and 0
// outside them. Only road curves are banked, not intersections or the S-curves of lane changes.
struct BankKnot {
  double s = 0.0;      // [m]
  double share = 0.0;  // [-1, 1]
};

// A stretch of road of one kind (kStraight, kUrban or kHighway).
struct RouteSection {
  double s_begin = 0.0;  // [m]
  double s_end = 0.0;    // [m]
  Scenario road_kind = Scenario::kUrban;
};

// A lane change: two opposite S-curves that end with the heading they started with.
struct LaneChange {
  double s_begin = 0.0;         // [m]
  double s_end = 0.0;           // [m]
  double lateral_offset = 0.0;  // sideways shift of the path, positive to the left [m]
};

struct RoadPlan {
  double initial_heading_enu = 0.0;      // heading at s = 0, counter-clockwise from east [rad]
  std::vector<CurvatureKnot> curvature;  // first knot at s = 0, s strictly increasing
  std::vector<BankKnot> bank;            // s strictly increasing; empty: no banked curves
  std::vector<double> stop_points;       // where the car must stop, increasing [m]
  std::vector<RouteSection> sections;    // consecutive, covering [0, length]; may be empty
  std::vector<LaneChange> lane_changes;  // increasing s

  double length() const { return curvature.empty() ? 0.0 : curvature.back().s; }  // [m]
};

// Urban grid: blocks, 90-degree turns at intersections, stops, the odd roundabout. Turns keep the
// heading within +-90 degrees of the section's first heading, so a section never crosses itself.
struct UrbanPlanOptions {
  double min_block_m = 80.0;   // straight between intersections [m]
  double max_block_m = 250.0;  // [m]
  // The first block of an urban section is short and ends in a stop and a turn, so that even a
  // short log shows both.
  double first_block_m = 90.0;          // [m]
  double min_turn_radius_m = 10.0;      // of the arc of a 90-degree turn [m]
  double max_turn_radius_m = 25.0;      // [m]
  double transition_fraction = 0.3;     // share of a turn's heading change in each clothoid, (0, 1)
  double turn_probability = 0.6;        // per intersection
  double stop_probability = 0.5;        // per intersection
  double roundabout_probability = 0.1;  // per intersection, instead of a crossing or turn
  double stop_line_gap_m = 4.0;         // stop line before the intersection [m]
  double crossing_m = 15.0;             // straight through an intersection [m]

  void Check() const;
};

// The most lanes a highway carriageway has: the world lays out markings and traffic per lane, so
// the count is bounded (real motorways have at most ~8 a side).
constexpr int kMaxHighwayLanes = 8;

// Highway: long straights with lane changes, long curves with clothoid transitions.
struct HighwayPlanOptions {
  double min_straight_m = 300.0;                // [m]
  double max_straight_m = 1200.0;               // [m]
  double min_curve_radius_m = 400.0;            // [m]
  double max_curve_radius_m = 1500.0;           // [m]
  double min_curve_angle = rad_from_deg(10.0);  // heading change of one curve [rad]
  double max_curve_angle = rad_from_deg(40.0);  // [rad]
  double min_transition_m = 60.0;               // clothoid length [m]
  double max_transition_m = 150.0;              // [m]
  double lane_change_probability = 0.6;         // per straight
  double min_lane_change_m = 150.0;  // length of a lane change [m]; 150 m at 3.5 m is R >= 800 m
  double max_lane_change_m = 250.0;  // [m]
  double lane_width_m = 3.5;         // [m]
  int lanes = 3;                     // lanes in the driving direction, [2, kMaxHighwayLanes]
  // Curves are banked towards their inside, fully at this radius or less and in proportion to
  // the curvature above it (superelevation grows with curvature).
  double full_bank_radius_m = 400.0;  // [m]

  void Check() const;
};

// Mixed: urban and highway sections alternate, urban first.
struct MixedPlanOptions {
  double min_urban_m = 500.0;     // [m]
  double max_urban_m = 1000.0;    // [m]
  double min_highway_m = 1500.0;  // [m]
  double max_highway_m = 3000.0;  // [m]

  void Check() const;
};

// City: the urban grid of a town centre: blocks of 40-120 m, a turn at 80 % of the intersections
// (left and right alternate, as on a grid), a stop at 60 %, tighter corners (8-20 m).
UrbanPlanOptions city_plan_options();

struct RoadPlanOptions {
  UrbanPlanOptions urban;
  UrbanPlanOptions city = city_plan_options();
  HighwayPlanOptions highway;
  MixedPlanOptions mixed;

  void Check() const;
};

// A plan at least `min_length_m` long [m], starting at s = 0 with `initial_heading_enu` [rad].
// Throws std::invalid_argument on bad options or a length that is not in (0, 1e6] m.
RoadPlan generate_road_plan(Scenario scenario, double min_length_m, double initial_heading_enu,
                            Random& rng, const RoadPlanOptions& options = {});

}  // namespace x2car::sim
