#include "x2car/sim/route.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/scenario.hpp"

namespace x2car::sim {
namespace {

constexpr std::array kScenarios = {Scenario::kStraight, Scenario::kUrban, Scenario::kHighway,
                                   Scenario::kMixed, Scenario::kCity};

// A route on a flat road (no grade, no crossfall) from curvature knots.
Route flat_route(std::vector<CurvatureKnot> knots, double initial_heading = 0.0) {
  RoadPlan plan;
  plan.initial_heading_enu = initial_heading;
  plan.curvature = std::move(knots);
  return Route(std::move(plan), VerticalProfile{});
}

// Knots of a 90-degree left turn of `radius` [m] between two 20 m straights, with clothoids that
// take 30 % of the heading change each (as the urban generator lays them out).
std::vector<CurvatureKnot> right_angle_turn(double radius) {
  const double transition = 0.3 * kPi / 2.0 * radius;
  const double arc = kPi / 2.0 * radius - transition;
  const double k = 1.0 / radius;
  return {{0.0, 0.0},
          {20.0, 0.0},
          {20.0 + transition, k},
          {20.0 + transition + arc, k},
          {20.0 + 2.0 * transition + arc, 0.0},
          {40.0 + 2.0 * transition + arc, 0.0}};
}

// The plan is built from the raw output of mt19937_64 (fixed by the C++ standard) with
// arithmetic only, so its layout must be exactly this on every platform and standard library.
TEST(Route, PlanIsTheSameOnEveryPlatform) {
  const Route route = generate_route(Scenario::kUrban, 1000.0, 1);
  EXPECT_EQ(route.length(), 0x1.11f50b1a72ddep+10);
  EXPECT_EQ(route.stop_points().size(), 5u);
  EXPECT_EQ(route.stop_points().front(), 86.0);
  EXPECT_EQ(route.plan().initial_heading_enu, 0x1.19829c5963114p+1);
}

TEST(Route, IsDeterministic) {
  for (Scenario scenario : kScenarios) {
    const Route a = generate_route(scenario, 3000.0, 7);
    const Route b = generate_route(scenario, 3000.0, 7);
    const Route c = generate_route(scenario, 3000.0, 8);
    ASSERT_EQ(a.length(), b.length());
    EXPECT_EQ(a.stop_points(), b.stop_points());
    double largest_difference = 0.0;
    for (double s = 0.0; s < a.length() && s < c.length(); s += 10.0) {
      const RoutePoint p = a.at(s), q = b.at(s), r = c.at(s);
      ASSERT_EQ(p.x, q.x);  // identical, not merely close
      ASSERT_EQ(p.y, q.y);
      ASSERT_EQ(p.z, q.z);
      ASSERT_EQ(p.heading_enu, q.heading_enu);
      ASSERT_EQ(p.crossfall, q.crossfall);
      largest_difference = std::max(largest_difference, std::hypot(p.x - r.x, p.y - r.y));
    }
    EXPECT_GT(largest_difference, 10.0) << to_string(scenario) << ": seed 8 gives the same route";
  }
}

// heading = direction of d(x, y)/ds, curvature = d heading / ds, grade = dz/ds, and the rates
// are the derivatives of grade and crossfall, by central differences of +-1 cm.
TEST(Route, AnglesAndSlopesAreTheDerivativesOfThePath) {
  const double d = 0.01;  // [m]
  for (Scenario scenario : kScenarios) {
    for (std::uint64_t seed : {1u, 2u}) {
      const Route route = generate_route(scenario, 3000.0, seed);
      const auto& bank = route.plan().bank;
      for (double s = d; s < route.length() - d; s += 0.37) {
        const RoutePoint before = route.at(s - d), point = route.at(s), after = route.at(s + d);
        const double chord = std::atan2(after.y - before.y, after.x - before.x);
        ASSERT_NEAR(angle_difference(chord, point.heading_enu), 0.0, 1e-4) << s;
        const double turn = angle_difference(after.heading_enu, before.heading_enu) / (2.0 * d);
        ASSERT_NEAR(turn, point.curvature, 1e-4) << s;
        ASSERT_NEAR((after.z - before.z) / (2.0 * d), point.grade, 1e-6) << s;
        ASSERT_NEAR((after.grade - before.grade) / (2.0 * d), point.grade_rate, 1e-6) << s;
        const bool at_bank_knot = std::any_of(
            bank.begin(), bank.end(), [&](const BankKnot& k) { return std::abs(k.s - s) <= d; });
        if (at_bank_knot) continue;  // the bank is piecewise linear: no derivative at its knots
        ASSERT_NEAR((after.crossfall - before.crossfall) / (2.0 * d), point.crossfall_rate, 1e-6)
            << s;
      }
    }
  }
}

TEST(Route, GradeAndCrossfallStayWithinTheirLimits) {
  for (Scenario scenario : kScenarios) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const Route route = generate_route(scenario, 5000.0, seed);
      double max_grade = 0.0, max_crossfall = 0.0;
      for (double s = 0.0; s <= route.length(); s += 1.0) {
        const RoutePoint point = route.at(s);
        max_grade = std::max(max_grade, std::abs(point.grade));
        max_crossfall = std::max(max_crossfall, std::abs(point.crossfall));
      }
      EXPECT_LE(max_grade, 0.06);
      EXPECT_LE(max_crossfall, 0.03);
      EXPECT_LE(route.max_abs_grade(), 0.06);
      // Not flat: the profile really varies.
      EXPECT_GT(max_grade, 0.01) << to_string(scenario) << " seed " << seed;
      EXPECT_GT(max_crossfall, 0.003) << to_string(scenario) << " seed " << seed;
    }
  }
  RouteOptions gentle;
  gentle.vertical.max_grade = 0.02;
  const Route route = generate_route(Scenario::kUrban, 3000.0, 1, gentle);
  for (double s = 0.0; s <= route.length(); s += 1.0) ASSERT_LE(std::abs(route.at(s).grade), 0.02);
}

TEST(Route, RightAngleTurnTurnsByNinetyDegrees) {
  for (double radius : {10.0, 25.0}) {
    const Route route = flat_route(right_angle_turn(radius), 3.0);  // heading near the +-pi seam
    const RoutePoint start = route.at(20.0), end = route.at(route.length() - 20.0);
    EXPECT_NEAR(angle_difference(end.heading_enu, start.heading_enu), kPi / 2.0, 1e-12);
    EXPECT_NEAR(route.max_abs_curvature(0.0, route.length()), 1.0 / radius, 1e-15);
  }
}

TEST(Route, ArcsIntegrateToCircles) {
  const double radius = 20.0, k = 1.0 / radius;
  // A quarter circle to the left from the origin heading east ends at (R, R) heading north.
  const Route quarter = flat_route({{0.0, k}, {kPi / 2.0 * radius, k}});
  const RoutePoint end = quarter.at(quarter.length());
  EXPECT_NEAR(end.x, radius, 1e-9);
  EXPECT_NEAR(end.y, radius, 1e-9);
  EXPECT_NEAR(end.heading_enu, kPi / 2.0, 1e-12);
  // Ten full turns to the right come back to the start: no drift over 12,566 table steps.
  const Route circles = flat_route({{0.0, -k}, {20.0 * kPi * radius, -k}}, 1.0);
  const RoutePoint back = circles.at(circles.length());
  EXPECT_NEAR(back.x, 0.0, 1e-9);
  EXPECT_NEAR(back.y, 0.0, 1e-9);
  // Half way round the first circle: the point opposite the start across the centre.
  const RoutePoint opposite = circles.at(kPi * radius);
  EXPECT_NEAR(std::hypot(opposite.x, opposite.y), 2.0 * radius, 1e-9);
}

TEST(Route, UrbanTurnsAreRightAnglesAndStopsAreOnStraights) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Route route = generate_route(Scenario::kUrban, 5000.0, seed);
    const auto& knots = route.plan().curvature;
    const double first_heading = route.plan().initial_heading_enu;
    int turned_straights = 0;
    for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
      if (knots[i].curvature != 0.0 || knots[i + 1].curvature != 0.0) continue;
      const double turned = angle_difference(route.at(knots[i].s).heading_enu, first_heading);
      const double quarters = turned / (kPi / 2.0);
      EXPECT_NEAR(quarters, std::round(quarters), 1e-9) << "seed " << seed << " s " << knots[i].s;
      EXPECT_LE(std::abs(std::round(quarters)), 1.0);  // within +-90 degrees of the first heading
      if (std::round(quarters) != 0.0) ++turned_straights;
    }
    EXPECT_GT(turned_straights, 0) << "seed " << seed;
    ASSERT_FALSE(route.stop_points().empty());
    for (double stop : route.stop_points()) EXPECT_EQ(route.curvature_at(stop), 0.0);
    ASSERT_EQ(route.sections().size(), 1u);
    EXPECT_EQ(route.sections()[0].road_kind, Scenario::kUrban);
    EXPECT_EQ(route.sections()[0].s_end, route.length());
    EXPECT_GE(route.length(), 5000.0);
  }
}

// Right-angle turns (from one straight to the next at another quarter heading) per km.
double turns_per_km(const Route& route) {
  const auto& knots = route.plan().curvature;
  int turns = 0;
  double last_quarters = 0.0;
  for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
    if (knots[i].curvature != 0.0 || knots[i + 1].curvature != 0.0) continue;
    const double quarters = std::round(
        angle_difference(route.at(knots[i].s).heading_enu, route.plan().initial_heading_enu) /
        (kPi / 2.0));
    if (quarters != last_quarters) ++turns;
    last_quarters = quarters;
  }
  return 1000.0 * turns / route.length();
}

// The city scenario: an urban road (section kind, so the urban world and driving style) with short
// blocks and several right-angle turns per km, more than the urban scenario's.
TEST(Route, CityTurnsMoreOftenThanUrban) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Route city = generate_route(Scenario::kCity, 3000.0, seed);
    const Route urban = generate_route(Scenario::kUrban, 3000.0, seed);
    ASSERT_EQ(city.sections().size(), 1u);
    EXPECT_EQ(city.sections()[0].road_kind, Scenario::kUrban);
    EXPECT_GE(turns_per_km(city), 6.0) << "seed " << seed;
    EXPECT_GT(turns_per_km(city), turns_per_km(urban)) << "seed " << seed;
    EXPECT_GE(city.stop_points().size() / (city.length() / 1000.0), 4.0) << "seed " << seed;
  }
}

TEST(Route, HighwayCurvesAreGentleAndLaneChangesShiftOneLane) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Route route = generate_route(Scenario::kHighway, 20000.0, seed);
    EXPECT_LE(route.max_abs_curvature(0.0, route.length()), 1.0 / 400.0 + 1e-15);
    EXPECT_TRUE(route.stop_points().empty());
    ASSERT_GE(route.lane_changes().size(), 2u) << "seed " << seed;
    for (const LaneChange& change : route.lane_changes()) {
      const RoutePoint begin = route.at(change.s_begin), end = route.at(change.s_end);
      EXPECT_NEAR(angle_difference(end.heading_enu, begin.heading_enu), 0.0, 1e-12);
      const double left = -std::sin(begin.heading_enu) * (end.x - begin.x) +
                          std::cos(begin.heading_enu) * (end.y - begin.y);
      EXPECT_NEAR(std::abs(change.lateral_offset), 3.5, 1e-12);
      EXPECT_NEAR(left, change.lateral_offset, 0.005);  // small-angle design formula: ~0.6 mm off
    }
    // Curves are banked towards their inside: a left curve lowers the left edge (crossfall < 0).
    // Lane changes are not banked.
    const auto& camber = route.vertical_profile().crossfall_waves;
    int banked = 0;
    for (double s = 0.0; s <= route.length(); s += 5.0) {
      const RoutePoint point = route.at(s);
      double bank = point.crossfall;
      for (const SineWave& w : camber) {
        bank -= w.amplitude * std::sin(2.0 * kPi / w.wavelength_m * s + w.phase);
      }
      const bool in_lane_change =
          std::any_of(route.lane_changes().begin(), route.lane_changes().end(),
                      [&](const LaneChange& c) { return s >= c.s_begin && s <= c.s_end; });
      if (in_lane_change || point.curvature == 0.0) {
        ASSERT_NEAR(bank, 0.0, 1e-12) << s;
        continue;
      }
      ASSERT_LT(bank * point.curvature, 0.0) << s;
      ASSERT_LE(std::abs(bank), 0.015 + 1e-12);
      ++banked;
    }
    EXPECT_GT(banked, 100);
  }
}

TEST(Route, StraightScenarioIsOneStraightRoad) {
  const Route route = generate_route(Scenario::kStraight, 2000.0, 3);
  EXPECT_GE(route.length(), 2000.0);
  EXPECT_EQ(route.max_abs_curvature(0.0, route.length()), 0.0);
  EXPECT_TRUE(route.stop_points().empty());
  EXPECT_EQ(route.at(route.length()).heading_enu, route.at(0.0).heading_enu);
}

TEST(Route, MixedAlternatesUrbanAndHighwaySections) {
  const Route route = generate_route(Scenario::kMixed, 8000.0, 4);
  const auto& sections = route.sections();
  ASSERT_GE(sections.size(), 3u);
  EXPECT_EQ(sections.front().s_begin, 0.0);
  EXPECT_EQ(sections.back().s_end, route.length());
  for (std::size_t i = 0; i < sections.size(); ++i) {
    EXPECT_EQ(sections[i].road_kind, i % 2 == 0 ? Scenario::kUrban : Scenario::kHighway);
    if (i > 0) {
      EXPECT_EQ(sections[i].s_begin, sections[i - 1].s_end);
    }
  }
}

TEST(Route, RejectsBadInput) {
  const Route route = generate_route(Scenario::kUrban, 500.0, 1);
  EXPECT_THROW(route.at(-0.001), std::out_of_range);
  EXPECT_THROW(route.at(route.length() + 0.001), std::out_of_range);
  EXPECT_THROW(generate_route(Scenario::kUrban, 0.0, 1), std::invalid_argument);
  RouteOptions options;
  options.vertical.max_grade = -0.01;
  EXPECT_THROW(generate_route(Scenario::kUrban, 500.0, 1, options), std::invalid_argument);
  options = {};
  options.plan.urban.min_turn_radius_m = 30.0;  // above the maximum
  EXPECT_THROW(generate_route(Scenario::kUrban, 500.0, 1, options), std::invalid_argument);
  // 1e8 waves stalled a 5 s drive for minutes (every point sums them all).
  options = {};
  options.vertical.waves = 100000000;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.vertical.waves = 100;
  EXPECT_NO_THROW(options.Check());
  options = {};
  options.table_step_m = 1e-6;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.plan.highway.lanes = 1000000;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_THROW(flat_route({{0.0, 0.0}, {10.0, 0.0}, {5.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(flat_route({{1.0, 0.0}, {10.0, 0.0}}), std::invalid_argument);
  RoadPlan plan;
  plan.curvature = {{0.0, 0.0}, {10.0, 0.0}};
  plan.stop_points = {11.0};
  EXPECT_THROW(Route(plan, VerticalProfile{}), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::sim
