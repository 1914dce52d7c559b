#include "x2car/sim/route.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "x2car/core/options_check.hpp"

namespace x2car::sim {
namespace {

// Random streams (Random::derive_seed) for the parts of a route, so that changing one does not move
// the other.
constexpr std::uint64_t kPlanStream = 1;
constexpr std::uint64_t kProfileStream = 2;
constexpr double kMaxTableNodes = 2e7;  // guards memory against a tiny step on a long route

// 4-point Gauss-Legendre rule on [-1, 1]: exact for polynomials of degree 7. On a 0.1 m step the
// heading changes by < 0.01 rad, so cos and sin of it are integrated to rounding.
constexpr std::array<double, 4> kGaussNodes = {-0.8611363115940526, -0.3399810435848563,
                                               0.3399810435848563, 0.8611363115940526};
constexpr std::array<double, 4> kGaussWeights = {0.3478548451374538, 0.6521451548625461,
                                                 0.6521451548625461, 0.3478548451374538};

double wavenumber(const SineWave& wave) { return 2.0 * kPi / wave.wavelength_m; }

double wave_sum(const std::vector<SineWave>& waves, double s) {
  double sum = 0.0;
  for (const SineWave& wave : waves)
    sum += wave.amplitude * std::sin(wavenumber(wave) * s + wave.phase);
  return sum;
}

double wave_sum_rate(const std::vector<SineWave>& waves, double s) {
  double sum = 0.0;
  for (const SineWave& wave : waves) {
    const double k = wavenumber(wave);
    sum += wave.amplitude * k * std::cos(k * s + wave.phase);
  }
  return sum;
}

// Integral of the waves from 0 to s: z(s) for grade waves, with z(0) = 0.
double wave_sum_integral(const std::vector<SineWave>& waves, double s) {
  double sum = 0.0;
  for (const SineWave& wave : waves) {
    const double k = wavenumber(wave);
    sum += wave.amplitude / k * (std::cos(wave.phase) - std::cos(k * s + wave.phase));
  }
  return sum;
}

double amplitude_sum(const std::vector<SineWave>& waves) {
  double sum = 0.0;
  for (const SineWave& wave : waves) sum += std::abs(wave.amplitude);
  return sum;
}

void check_plan(const RoadPlan& plan) {
  const auto& knots = plan.curvature;
  if (knots.size() < 2) reject_argument("route: the plan needs at least 2 curvature knots");
  if (knots.front().s != 0.0) reject_argument("route: the first knot must be at s = 0");
  if (!std::isfinite(plan.initial_heading_enu))
    reject_argument("route: initial heading is not finite");
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i].s) || !std::isfinite(knots[i].curvature)) {
      reject_argument("route: knot {} is not finite", i);
    }
    if (i > 0 && !(knots[i].s > knots[i - 1].s))
      reject_argument("route: knot {} does not advance s", i);
  }
  const auto& bank = plan.bank;
  for (std::size_t i = 0; i < bank.size(); ++i) {
    if (!(bank[i].s >= 0.0 && bank[i].s <= plan.length() && std::abs(bank[i].share) <= 1.0) ||
        (i > 0 && !(bank[i].s > bank[i - 1].s))) {
      reject_argument("route: bank knot {} is outside the route, out of order or beyond [-1, 1]",
                      i);
    }
  }
  if (!bank.empty() && (bank.front().share != 0.0 || bank.back().share != 0.0)) {
    reject_argument("route: the bank must start and end at share 0, so that it is continuous");
  }
  for (std::size_t i = 0; i < plan.stop_points.size(); ++i) {
    const double stop = plan.stop_points[i];
    if (!(stop > 0.0 && stop <= plan.length()) || (i > 0 && !(stop > plan.stop_points[i - 1]))) {
      reject_argument("route: stop point {} at {} m is outside (0, {}] or out of order", i, stop,
                      plan.length());
    }
  }
}

void check_profile(const VerticalProfile& profile) {
  for (const auto* waves : {&profile.grade_waves, &profile.crossfall_waves}) {
    for (const SineWave& wave : *waves) {
      if (!(std::isfinite(wave.amplitude) && std::isfinite(wave.phase) && wave.wavelength_m > 0.0 &&
            std::isfinite(wave.wavelength_m))) {
        reject_argument("route: a vertical-profile wave is not finite or has wavelength <= 0");
      }
    }
  }
  if (!(std::isfinite(profile.curve_bank) && profile.curve_bank >= 0.0)) {
    reject_argument("route: curve_bank must be finite and >= 0");
  }
}

std::vector<SineWave> draw_waves(Random& rng, int count, double total_amplitude,
                                 double min_wavelength, double max_wavelength) {
  std::vector<SineWave> waves(static_cast<std::size_t>(count));
  double weight_sum = 0.0;
  for (SineWave& wave : waves) {
    wave.amplitude = rng.uniform(0.5, 1.0);  // a weight for now
    wave.wavelength_m = rng.uniform(min_wavelength, max_wavelength);
    wave.phase = rng.uniform(0.0, 2.0 * kPi);
    weight_sum += wave.amplitude;
  }
  for (SineWave& wave : waves) wave.amplitude *= total_amplitude / weight_sum;
  return waves;
}

}  // namespace

Route::Route(RoadPlan plan, VerticalProfile profile, double table_step_m)
    : plan_(std::move(plan)), profile_(std::move(profile)), table_step_(table_step_m) {
  check_plan(plan_);
  check_profile(profile_);
  if (!(table_step_m > 0.0 && plan_.length() / table_step_m < kMaxTableNodes)) {
    reject_argument("route: table step {} m must be > 0 and give < {} nodes", table_step_m,
                    kMaxTableNodes);
  }
  knot_s_.reserve(plan_.curvature.size());
  knot_heading_.reserve(plan_.curvature.size());
  double heading = plan_.initial_heading_enu;
  for (std::size_t i = 0; i < plan_.curvature.size(); ++i) {
    const CurvatureKnot& knot = plan_.curvature[i];
    if (i > 0) {  // trapezoid: exact for kappa linear in s
      const CurvatureKnot& previous = plan_.curvature[i - 1];
      heading += 0.5 * (previous.curvature + knot.curvature) * (knot.s - previous.s);
    }
    knot_s_.push_back(knot.s);
    knot_heading_.push_back(heading);
  }
  build_table();
}

std::size_t Route::piece_index(double s) const {
  const auto after = std::upper_bound(knot_s_.begin(), knot_s_.end(), s);
  const auto index =
      static_cast<std::size_t>(std::max<std::ptrdiff_t>(after - knot_s_.begin() - 1, 0));
  return std::min(index, knot_s_.size() - 2);
}

double Route::curvature_slope(std::size_t piece) const {
  return (plan_.curvature[piece + 1].curvature - plan_.curvature[piece].curvature) /
         (knot_s_[piece + 1] - knot_s_[piece]);
}

// heading(s) = heading_j + kappa_j d + slope_j d^2 / 2 with d = s - s_j: kappa integrated.
double Route::heading_unwrapped(double s) const {
  const std::size_t j = piece_index(s);
  const double d = s - knot_s_[j];
  return knot_heading_[j] + plan_.curvature[j].curvature * d + 0.5 * curvature_slope(j) * d * d;
}

double Route::curvature_at(double s) const {
  const std::size_t j = piece_index(s);
  return plan_.curvature[j].curvature + curvature_slope(j) * (s - knot_s_[j]);
}

double Route::grade_at(double s) const { return wave_sum(profile_.grade_waves, s); }

double Route::grade_rate_at(double s) const { return wave_sum_rate(profile_.grade_waves, s); }

namespace {

// The bank knot pair around s, or nullptr outside the banked stretches (share 0 there).
const BankKnot* bank_piece(const std::vector<BankKnot>& bank, double s) {
  const auto after =
      std::upper_bound(bank.begin(), bank.end(), s,
                       [](double value, const BankKnot& knot) { return value < knot.s; });
  if (after == bank.begin() || after == bank.end()) return nullptr;
  return &*(after - 1);
}

}  // namespace

double Route::bank_share(double s) const {
  const BankKnot* knot = bank_piece(plan_.bank, s);
  if (knot == nullptr) return 0.0;
  const BankKnot& next = knot[1];
  return knot->share + (next.share - knot->share) * (s - knot->s) / (next.s - knot->s);
}

double Route::bank_share_rate(double s) const {
  const BankKnot* knot = bank_piece(plan_.bank, s);
  return knot == nullptr ? 0.0 : (knot[1].share - knot->share) / (knot[1].s - knot->s);
}

double Route::max_abs_curvature(double s_begin, double s_end) const {
  double result = std::max(std::abs(curvature_at(s_begin)), std::abs(curvature_at(s_end)));
  for (std::size_t k = piece_index(s_begin) + 1; k < knot_s_.size() && knot_s_[k] < s_end; ++k) {
    result = std::max(result, std::abs(plan_.curvature[k].curvature));
  }
  return result;
}

double Route::max_abs_grade() const { return amplitude_sum(profile_.grade_waves); }

namespace {

// Integral of (cos, sin)(heading) over [a, b] within one piece, where the heading is quadratic.
void add_piece_integral(double a, double b, double heading_at_knot, double knot_s, double curvature,
                        double slope, double& x, double& y) {
  const double half = 0.5 * (b - a);
  const double middle = 0.5 * (a + b);
  for (std::size_t g = 0; g < kGaussNodes.size(); ++g) {
    const double d = middle + half * kGaussNodes[g] - knot_s;
    const double heading = heading_at_knot + curvature * d + 0.5 * slope * d * d;
    x += half * kGaussWeights[g] * std::cos(heading);
    y += half * kGaussWeights[g] * std::sin(heading);
  }
}

}  // namespace

void Route::build_table() {
  const auto nodes = static_cast<std::size_t>(std::floor(length() / table_step_)) + 1;
  table_x_.assign(nodes, 0.0);
  table_y_.assign(nodes, 0.0);
  std::size_t j = 0;  // piece of the current step's start
  for (std::size_t i = 1; i < nodes; ++i) {
    double a = static_cast<double>(i - 1) * table_step_;
    const double b = std::min(static_cast<double>(i) * table_step_, length());
    double x = table_x_[i - 1], y = table_y_[i - 1];
    while (a < b) {  // split the step at the knots inside it
      while (j + 2 < knot_s_.size() && knot_s_[j + 1] <= a) ++j;
      const double piece_end = std::min(b, knot_s_[j + 1]);
      add_piece_integral(a, piece_end, knot_heading_[j], knot_s_[j], plan_.curvature[j].curvature,
                         curvature_slope(j), x, y);
      a = piece_end;
    }
    table_x_[i] = x;
    table_y_[i] = y;
  }
}

RoutePoint Route::at(double s) const {
  if (!(s >= 0.0 && s <= length())) {
    throw std::out_of_range(fmt::format("route: s = {} m is outside [0, {}] m", s, length()));
  }
  RoutePoint point;
  point.s = s;
  const auto node = std::min(static_cast<std::size_t>(s / table_step_), table_x_.size() - 1);
  double x = table_x_[node], y = table_y_[node];
  for (double a = static_cast<double>(node) * table_step_; a < s;) {
    const std::size_t j = piece_index(a);
    const double piece_end = std::min(s, knot_s_[j + 1]);
    add_piece_integral(a, piece_end, knot_heading_[j], knot_s_[j], plan_.curvature[j].curvature,
                       curvature_slope(j), x, y);
    a = piece_end;
  }
  point.x = x;
  point.y = y;
  point.z = wave_sum_integral(profile_.grade_waves, s);
  point.heading_enu = wrap_angle(heading_unwrapped(s));
  point.curvature = curvature_at(s);
  point.grade = grade_at(s);
  point.grade_rate = grade_rate_at(s);
  point.crossfall = wave_sum(profile_.crossfall_waves, s) + profile_.curve_bank * bank_share(s);
  point.crossfall_rate =
      wave_sum_rate(profile_.crossfall_waves, s) + profile_.curve_bank * bank_share_rate(s);
  return point;
}

void VerticalProfileOptions::Check() const {
  const OptionsCheck check("VerticalProfileOptions");
  check.in_range("max_grade", max_grade, 0.0, 0.5, Bounds::kOpenMax);
  check.in_range("max_crossfall", max_crossfall, 0.0, 0.5, Bounds::kOpenMax);
  check.probability("curve_bank_share", curve_bank_share);
  check.positive("min_grade_wavelength_m", min_grade_wavelength_m);
  check.ordered("min_grade_wavelength_m", min_grade_wavelength_m, "max_grade_wavelength_m",
                max_grade_wavelength_m);
  check.positive("min_crossfall_wavelength_m", min_crossfall_wavelength_m);
  check.ordered("min_crossfall_wavelength_m", min_crossfall_wavelength_m,
                "max_crossfall_wavelength_m", max_crossfall_wavelength_m);
  // Every route point sums all waves: a few make a natural profile, millions only stall.
  check.in_range("waves", waves, 1, 100);
}

void RouteOptions::Check() const {
  plan.Check();
  vertical.Check();
  // Below a centimetre the table only costs memory (positions are exact at 2 m steps).
  OptionsCheck("RouteOptions").in_range("table_step_m", table_step_m, 0.01, 10.0);
}

VerticalProfile generate_vertical_profile(Random& rng, const VerticalProfileOptions& options) {
  options.Check();
  VerticalProfile profile;
  profile.grade_waves = draw_waves(rng, options.waves, options.max_grade * rng.uniform(0.5, 1.0),
                                   options.min_grade_wavelength_m, options.max_grade_wavelength_m);
  const double camber = options.max_crossfall * (1.0 - options.curve_bank_share);
  profile.crossfall_waves =
      draw_waves(rng, options.waves, camber * rng.uniform(0.5, 1.0),
                 options.min_crossfall_wavelength_m, options.max_crossfall_wavelength_m);
  profile.curve_bank = options.max_crossfall * options.curve_bank_share;
  return profile;
}

Route generate_route(Scenario scenario, double min_length_m, std::uint64_t seed,
                     const RouteOptions& options) {
  options.Check();
  Random plan_rng(Random::derive_seed(seed, kPlanStream));
  const double initial_heading = plan_rng.uniform(-kPi, kPi);
  RoadPlan plan =
      generate_road_plan(scenario, min_length_m, initial_heading, plan_rng, options.plan);
  Random profile_rng(Random::derive_seed(seed, kProfileStream));
  VerticalProfile profile = generate_vertical_profile(profile_rng, options.vertical);
  return Route(std::move(plan), std::move(profile), options.table_step_m);
}

}  // namespace x2car::sim
