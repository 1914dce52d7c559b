// The road the simulated car drives: a 3-D curve in the local ENU world, built from a plan view
// (curvature as a piecewise-linear function of arc length, see RoadPlan) and a vertical profile
// (grade and crossfall as smooth functions of arc length).
//
// s is the horizontal (plan) arc length from the start [m]. The plan is integrated exactly: the
// heading is a piecewise quadratic in s, and x, y = integral of (cos, sin)(heading) ds is tabulated
// every table_step_m by Gauss-Legendre quadrature and completed from the nearest table node on
// each query, so positions are exact to rounding (~1e-9 m over tens of kilometres).
#pragma once

#include <cstdint>
#include <vector>

#include "x2car/sim/scenario.hpp"

namespace x2car::sim {

struct RoutePoint {
  double s = 0.0;               // horizontal arc length from the start [m]
  double x = 0.0;               // east [m]
  double y = 0.0;               // north [m]
  double z = 0.0;               // up, 0 at the start [m]
  double heading_enu = 0.0;     // plan tangent, counter-clockwise from east, in (-pi, pi] [rad]
  double curvature = 0.0;       // d heading / ds in the plan, positive left [1/m]
  double grade = 0.0;           // dz / ds, positive uphill [m/m]
  double crossfall = 0.0;       // sideways slope: rise per metre towards the left [m/m]
  double grade_rate = 0.0;      // d grade / ds [1/m]
  double crossfall_rate = 0.0;  // d crossfall / ds [1/m]
};

// amplitude * sin(2 pi s / wavelength + phase).
struct SineWave {
  double amplitude = 0.0;     // [m/m]
  double wavelength_m = 1.0;  // [m]
  double phase = 0.0;         // [rad]
};

// grade(s) = sum of grade_waves; crossfall(s) = sum of crossfall_waves + the bank of curves,
// curve_bank * share(s) with the share from RoadPlan::bank (a left curve lowers the left edge,
// which is negative crossfall).
struct VerticalProfile {
  std::vector<SineWave> grade_waves;
  std::vector<SineWave> crossfall_waves;
  double curve_bank = 0.0;  // crossfall of a fully banked curve, >= 0 [m/m]
};

class Route {
 public:
  // Throws std::invalid_argument on a malformed plan (fewer than 2 knots, first not at 0, s not
  // strictly increasing, non-finite values, stop points outside (0, length], bank knots out of
  // order or not starting and ending at share 0) or profile.
  Route(RoadPlan plan, VerticalProfile profile, double table_step_m = 0.1);

  // Throws std::out_of_range when s is outside [0, length()].
  RoutePoint at(double s) const;
  double curvature_at(double s) const;   // [1/m], cheaper than at(s).curvature
  double grade_at(double s) const;       // [m/m]
  double grade_rate_at(double s) const;  // [1/m]

  double length() const { return plan_.length(); }  // [m]
  const std::vector<double>& stop_points() const { return plan_.stop_points; }
  const std::vector<RouteSection>& sections() const { return plan_.sections; }
  const std::vector<LaneChange>& lane_changes() const { return plan_.lane_changes; }
  const RoadPlan& plan() const { return plan_; }
  const VerticalProfile& vertical_profile() const { return profile_; }

  // Largest |curvature| on [s_begin, s_end] [1/m] (exact: kappa is linear between knots).
  double max_abs_curvature(double s_begin, double s_end) const;
  // Upper bound of |grade| over the whole route: the sum of the wave amplitudes [m/m].
  double max_abs_grade() const;

 private:
  std::size_t piece_index(double s) const;  // knot that starts the piece holding s
  double heading_unwrapped(double s) const;
  double curvature_slope(std::size_t piece) const;  // d kappa / ds on a piece [1/m^2]
  double bank_share(double s) const;
  double bank_share_rate(double s) const;  // [1/m]
  void build_table();

  RoadPlan plan_;
  VerticalProfile profile_;
  double table_step_ = 0.1;                // [m]
  std::vector<double> knot_s_;             // plan_.curvature[i].s, for binary search [m]
  std::vector<double> knot_heading_;       // unwrapped heading at each knot [rad]
  std::vector<double> table_x_, table_y_;  // position every table_step_ [m]
};

struct VerticalProfileOptions {
  double max_grade = 0.06;      // |grade| never exceeds this [m/m]
  double max_crossfall = 0.03;  // |crossfall| never exceeds this [m/m]
  // Share of max_crossfall given to banking curves; the rest is the random camber.
  double curve_bank_share = 0.5;
  double min_grade_wavelength_m = 300.0;      // hills [m]
  double max_grade_wavelength_m = 1500.0;     // [m]
  double min_crossfall_wavelength_m = 100.0;  // camber changes [m]
  double max_crossfall_wavelength_m = 600.0;  // [m]
  int waves = 3;                              // sine waves summed for grade and for camber, >= 1

  void Check() const;  // throws std::invalid_argument
};

struct RouteOptions {
  RoadPlanOptions plan;
  VerticalProfileOptions vertical;
  // Position table spacing [m]. Each query integrates from the node below it, so this trades
  // memory only: positions stay exact to ~1e-12 m up to 2 m steps (1e-8 m at 10 m, R = 10 m).
  double table_step_m = 0.1;

  void Check() const;  // throws std::invalid_argument
};

// Draws a vertical profile: each wave gets a random wavelength and phase and a share of the total
// amplitude, which is itself drawn in [0.5, 1] of the limit, so the limits always hold.
VerticalProfile generate_vertical_profile(Random& rng, const VerticalProfileOptions& options);

// A procedural route at least `min_length_m` long [m] for the scenario. Starts at the ENU origin
// with a random heading. The same arguments give the same plan and profile on every platform
// (draws and layout use arithmetic only); positions then depend only on std::sin and std::cos.
Route generate_route(Scenario scenario, double min_length_m, std::uint64_t seed,
                     const RouteOptions& options = {});

}  // namespace x2car::sim
