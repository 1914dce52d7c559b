#include "x2car/sim/scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::sim {
namespace {

constexpr std::array<EnumName<Scenario>, 5> kScenarioNames{{
    {Scenario::kStraight, "straight"},
    {Scenario::kUrban, "urban"},
    {Scenario::kHighway, "highway"},
    {Scenario::kMixed, "mixed"},
    {Scenario::kCity, "city"},
}};

constexpr double kMaxPlanLength = 1e6;   // [m] guards memory against a length that cannot be meant
constexpr double kFinalStraight = 30.0;  // [m] so that the last turn or stop is not at the end
constexpr double kRoundaboutEntryAngle = rad_from_deg(40.0);  // deflection to the right [rad]
constexpr double kHighwayDriftLimit = kPi / 4.0;  // steer curves back beyond this drift [rad]
constexpr double kLaneChangeMargin = 50.0;        // straight road kept before and after one [m]

// True with the given probability.
bool chance(Random& rng, double probability) { return rng.uniform01() < probability; }

// Uniform in {0, ..., count - 1}, count >= 1.
int pick(Random& rng, int count) {
  return std::min(static_cast<int>(rng.uniform01() * count), count - 1);
}

// Appends knots to a plan as the road is laid out from s = 0 onwards.
class PlanBuilder {
 public:
  explicit PlanBuilder(double initial_heading_enu) {
    plan_.initial_heading_enu = initial_heading_enu;
    plan_.curvature.push_back({0.0, 0.0});
  }

  double s() const { return plan_.curvature.back().s; }

  void straight(double length) { knot(length, 0.0); }

  // Turns by `angle` [rad, positive left] on an arc of `radius` [m] entered and left through
  // clothoids of length `transition` [m]; each clothoid turns by half its length times 1 / radius.
  // A banked turn raises its outer edge by `bank_share` of the route's curve bank, in step with
  // the curvature: ramped over the clothoids, held over the arc.
  void turn(double angle, double radius, double transition, double bank_share = 0.0) {
    const double curvature = std::copysign(1.0 / radius, angle);
    const double arc = std::abs(angle) * radius - transition;
    const double share = -std::copysign(bank_share, angle);
    const bool banked = bank_share != 0.0;
    if (banked) bank_knot(0.0);
    knot(transition, curvature);
    if (banked) bank_knot(share);
    knot(arc, curvature);
    if (banked) bank_knot(share);
    knot(transition, 0.0);
    if (banked) bank_knot(0.0);
  }

  // Triangular curvature up and down over length / 2, then the mirror image: the heading returns,
  // and the sideways shift is integral of heading = peak_curvature * length^2 / 8 (small angles).
  void lane_change(double offset, double length) {
    const double peak_curvature = 8.0 * offset / (length * length);
    const double begin = s();
    knot(length / 4.0, peak_curvature);
    knot(length / 4.0, 0.0);
    knot(length / 4.0, -peak_curvature);
    knot(length / 4.0, 0.0);
    plan_.lane_changes.push_back({begin, s(), offset});
  }

  void stop_at(double stop_s) { plan_.stop_points.push_back(stop_s); }

  void section(double begin, Scenario road_kind) {
    plan_.sections.push_back({begin, s(), road_kind});
  }

  RoadPlan finish() {
    straight(kFinalStraight);
    if (!plan_.sections.empty()) plan_.sections.back().s_end = s();
    return std::move(plan_);
  }

 private:
  void knot(double length, double curvature) {
    if (length > 0.0) plan_.curvature.push_back({s() + length, curvature});
  }

  // A knot where one already is (a turn right after another) replaces it.
  void bank_knot(double share) {
    auto& bank = plan_.bank;
    if (!bank.empty() && bank.back().s == s()) {
      bank.back().share = share;
    } else {
      bank.push_back({s(), share});
    }
  }

  RoadPlan plan_;
};

// Left (+1) or right (-1) with equal odds.
int random_side(Random& rng) { return chance(rng, 0.5) ? 1 : -1; }

// Urban roundabout, right-hand traffic: deflect right, go round to the left, deflect right again.
// Leaves straight on (net 0) or turns left (net +90 degrees, allowed only when that does not take
// the heading beyond +90 degrees of the section's first heading).
void append_roundabout(PlanBuilder& builder, Random& rng, const UrbanPlanOptions& options,
                       int& quarter_turns) {
  const bool exit_left = quarter_turns <= 0 && chance(rng, 0.5);
  const double entry_radius = rng.uniform(options.min_turn_radius_m, options.max_turn_radius_m);
  const double ring_radius = rng.uniform(options.min_turn_radius_m, options.max_turn_radius_m);
  const double ring_angle = 2.0 * kRoundaboutEntryAngle + (exit_left ? kPi / 2.0 : 0.0);
  const double entry_transition =
      options.transition_fraction * kRoundaboutEntryAngle * entry_radius;
  builder.turn(-kRoundaboutEntryAngle, entry_radius, entry_transition);
  builder.turn(ring_angle, ring_radius, options.transition_fraction * ring_angle * ring_radius);
  builder.turn(-kRoundaboutEntryAngle, entry_radius, entry_transition);
  if (exit_left) ++quarter_turns;
}

// One intersection at the end of a block: maybe a stop line, then a turn, a roundabout or a
// crossing. `quarter_turns` is the heading relative to the section's first one, in -1, 0, +1.
void append_intersection(PlanBuilder& builder, Random& rng, const UrbanPlanOptions& options,
                         bool first, int& quarter_turns) {
  if (first || chance(rng, options.stop_probability)) {
    builder.stop_at(builder.s() - options.stop_line_gap_m);
  }
  if (!first && chance(rng, options.roundabout_probability)) {
    append_roundabout(builder, rng, options, quarter_turns);
    return;
  }
  if (!first && !chance(rng, options.turn_probability)) {
    builder.straight(options.crossing_m);
    return;
  }
  const int side = quarter_turns != 0 ? -quarter_turns : random_side(rng);
  const double radius = rng.uniform(options.min_turn_radius_m, options.max_turn_radius_m);
  builder.turn(side * kPi / 2.0, radius, options.transition_fraction * kPi / 2.0 * radius);
  quarter_turns += side;
}

void append_urban(PlanBuilder& builder, double end_s, Random& rng,
                  const UrbanPlanOptions& options) {
  int quarter_turns = 0;
  for (bool first = true; first || builder.s() < end_s; first = false) {
    builder.straight(first ? options.first_block_m
                           : rng.uniform(options.min_block_m, options.max_block_m));
    append_intersection(builder, rng, options, first, quarter_turns);
  }
}

// A highway straight, with a lane change in it when it is long enough and chance says so.
void append_highway_straight(PlanBuilder& builder, Random& rng, const HighwayPlanOptions& options,
                             int& lane) {
  const double length = rng.uniform(options.min_straight_m, options.max_straight_m);
  const double change = rng.uniform(options.min_lane_change_m, options.max_lane_change_m);
  if (length < change + 2.0 * kLaneChangeMargin || !chance(rng, options.lane_change_probability)) {
    builder.straight(length);
    return;
  }
  // Lane 0 is the rightmost; at either edge the only way is inwards.
  const int side = lane == 0 ? 1 : lane == options.lanes - 1 ? -1 : random_side(rng);
  const double before = rng.uniform(kLaneChangeMargin, length - change - kLaneChangeMargin);
  builder.straight(before);
  builder.lane_change(side * options.lane_width_m, change);
  builder.straight(length - before - change);
  lane += side;
}

void append_highway(PlanBuilder& builder, double end_s, Random& rng,
                    const HighwayPlanOptions& options) {
  int lane = pick(rng, options.lanes);
  double drift = 0.0;  // heading change since the section began [rad]
  while (builder.s() < end_s) {
    append_highway_straight(builder, rng, options, lane);
    const double angle = rng.uniform(options.min_curve_angle, options.max_curve_angle);
    const double radius = rng.uniform(options.min_curve_radius_m, options.max_curve_radius_m);
    // The two clothoids turn by transition / radius together; capping that at half the curve's
    // angle leaves at least half of it to the arc.
    const double transition = std::min(
        rng.uniform(options.min_transition_m, options.max_transition_m), 0.5 * angle * radius);
    const int side = drift > kHighwayDriftLimit    ? -1
                     : drift < -kHighwayDriftLimit ? 1
                                                   : random_side(rng);
    builder.turn(side * angle, radius, transition,
                 std::min(1.0, options.full_bank_radius_m / radius));
    drift += side * angle;
  }
}

void append_mixed(PlanBuilder& builder, double end_s, Random& rng, const RoadPlanOptions& options) {
  for (bool urban = true; builder.s() < end_s; urban = !urban) {
    const double begin = builder.s();
    if (urban) {
      append_urban(builder,
                   begin + rng.uniform(options.mixed.min_urban_m, options.mixed.max_urban_m), rng,
                   options.urban);
    } else {
      append_highway(builder,
                     begin + rng.uniform(options.mixed.min_highway_m, options.mixed.max_highway_m),
                     rng, options.highway);
    }
    builder.section(begin, urban ? Scenario::kUrban : Scenario::kHighway);
  }
}

}  // namespace

std::string to_string(Scenario scenario) { return enum_to_string(kScenarioNames, scenario); }

Scenario scenario_from_string(std::string_view name) {
  return enum_from_string(kScenarioNames, name, "scenario");
}

std::vector<std::string> scenario_names() { return enum_names(kScenarioNames); }

void DrivingStyle::Check() const {
  const OptionsCheck check("DrivingStyle");
  check.positive("min_speed_mps", min_speed_mps);
  check.ordered("min_speed_mps", min_speed_mps, "max_speed_mps", max_speed_mps);
  check.positive("min_stretch_m", min_stretch_m);
  check.ordered("min_stretch_m", min_stretch_m, "max_stretch_m", max_stretch_m);
  check.positive("max_lateral_acceleration", max_lateral_acceleration);
}

DrivingStyle default_driving_style(Scenario road_kind) {
  switch (road_kind) {
    case Scenario::kStraight:
      return {50.0 / 3.6, 70.0 / 3.6, 2.0, 300.0, 800.0};
    case Scenario::kUrban:
    case Scenario::kCity:
      return {20.0 / 3.6, 50.0 / 3.6, 3.0, 100.0, 300.0};
    case Scenario::kHighway:
      return {80.0 / 3.6, 120.0 / 3.6, 2.0, 800.0, 2000.0};
    case Scenario::kMixed:
      break;
  }
  reject_argument("no driving style for road kind '{}' (use urban or highway)",
                  to_string(road_kind));
}

UrbanPlanOptions city_plan_options() {
  UrbanPlanOptions city;
  city.min_block_m = 40.0;
  city.max_block_m = 120.0;
  city.first_block_m = 60.0;
  city.min_turn_radius_m = 8.0;
  city.max_turn_radius_m = 20.0;
  city.turn_probability = 0.8;
  city.stop_probability = 0.6;
  city.roundabout_probability = 0.05;
  return city;
}

void UrbanPlanOptions::Check() const {
  const OptionsCheck check("UrbanPlanOptions");
  check.positive("min_block_m", min_block_m);
  check.ordered("min_block_m", min_block_m, "max_block_m", max_block_m);
  check.positive("min_turn_radius_m", min_turn_radius_m);
  check.ordered("min_turn_radius_m", min_turn_radius_m, "max_turn_radius_m", max_turn_radius_m);
  check.non_negative("stop_line_gap_m", stop_line_gap_m);
  check.that(first_block_m > stop_line_gap_m, "first_block_m", "must be > stop_line_gap_m",
             first_block_m);
  check.that(min_block_m > stop_line_gap_m, "min_block_m", "must be > stop_line_gap_m",
             min_block_m);
  check.in_range("transition_fraction", transition_fraction, 0.0, 1.0, Bounds::kOpen);
  check.probability("turn_probability", turn_probability);
  check.probability("stop_probability", stop_probability);
  check.probability("roundabout_probability", roundabout_probability);
  check.positive("crossing_m", crossing_m);
}

void HighwayPlanOptions::Check() const {
  const OptionsCheck check("HighwayPlanOptions");
  check.positive("min_straight_m", min_straight_m);
  check.ordered("min_straight_m", min_straight_m, "max_straight_m", max_straight_m);
  check.positive("min_curve_radius_m", min_curve_radius_m);
  check.ordered("min_curve_radius_m", min_curve_radius_m, "max_curve_radius_m", max_curve_radius_m);
  check.positive("min_curve_angle", min_curve_angle);
  check.ordered("min_curve_angle", min_curve_angle, "max_curve_angle", max_curve_angle);
  check.in_range("max_curve_angle", max_curve_angle, 0.0, kPi / 2.0, Bounds::kOpen);
  check.positive("min_transition_m", min_transition_m);
  check.ordered("min_transition_m", min_transition_m, "max_transition_m", max_transition_m);
  check.positive("min_lane_change_m", min_lane_change_m);
  check.ordered("min_lane_change_m", min_lane_change_m, "max_lane_change_m", max_lane_change_m);
  check.probability("lane_change_probability", lane_change_probability);
  check.positive("lane_width_m", lane_width_m);
  check.positive("full_bank_radius_m", full_bank_radius_m);
  check.in_range("lanes", lanes, 2, kMaxHighwayLanes);
}

void MixedPlanOptions::Check() const {
  const OptionsCheck check("MixedPlanOptions");
  check.positive("min_urban_m", min_urban_m);
  check.ordered("min_urban_m", min_urban_m, "max_urban_m", max_urban_m);
  check.positive("min_highway_m", min_highway_m);
  check.ordered("min_highway_m", min_highway_m, "max_highway_m", max_highway_m);
}

void RoadPlanOptions::Check() const {
  urban.Check();
  city.Check();
  highway.Check();
  mixed.Check();
}

RoadPlan generate_road_plan(Scenario scenario, double min_length_m, double initial_heading_enu,
                            Random& rng, const RoadPlanOptions& options) {
  options.Check();
  if (!(min_length_m > 0.0 && min_length_m <= kMaxPlanLength)) {
    reject_argument("road plan: length must be in (0, {}] m, got {}", kMaxPlanLength, min_length_m);
  }
  if (!std::isfinite(initial_heading_enu))
    reject_argument("road plan: initial heading is not finite");
  PlanBuilder builder(initial_heading_enu);
  switch (scenario) {
    case Scenario::kStraight:
      builder.straight(min_length_m);
      break;
    case Scenario::kUrban:
      append_urban(builder, min_length_m, rng, options.urban);
      break;
    case Scenario::kHighway:
      append_highway(builder, min_length_m, rng, options.highway);
      break;
    case Scenario::kMixed:
      append_mixed(builder, min_length_m, rng, options);
      break;
    case Scenario::kCity:
      append_urban(builder, min_length_m, rng, options.city);
      break;
  }
  // A city is an urban road: its world, lanes and driving style are the urban ones.
  if (scenario == Scenario::kCity) builder.section(0.0, Scenario::kUrban);
  if (scenario != Scenario::kMixed && scenario != Scenario::kCity) builder.section(0.0, scenario);
  return builder.finish();
}

}  // namespace x2car::sim
