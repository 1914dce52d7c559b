#include "x2car/radar/radar_velocity_checks.hpp"

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::radar {
namespace {

Eigen::Matrix2d rotation(double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

// M(dt) = integral_0^dt R(-omega u) du = [[S, C], [-C, S]], S = sin(omega dt) / omega,
// C = (1 - cos(omega dt)) / omega.
Eigen::Matrix2d translation_integral(double omega, double dt) {
  const double turn = omega * dt;
  const double s = std::abs(turn) < 1e-6 ? dt : std::sin(turn) / omega;
  const double c = std::abs(turn) < 1e-6 ? 0.5 * omega * dt * dt : (1.0 - std::cos(turn)) / omega;
  return (Eigen::Matrix2d() << s, c, -c, s).finished();
}

Eigen::Vector2d position_in_radar(const RadarSample& sample) {
  return sample.range * Eigen::Vector2d(std::cos(sample.azimuth), std::sin(sample.azimuth));
}

std::string percent(double fraction) { return fmt::format("{:.0f} %", 100.0 * fraction); }

}  // namespace

DisplacementCheck check_static_displacement(std::span<const RadarSample> samples,
                                            std::span<const std::uint8_t> static_mask,
                                            const VelocityModel& model,
                                            const RadarVelocityMethodOptions& options) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (static_mask[i]) order.push_back(i);
  }
  std::ranges::stable_sort(order, {}, [&](std::size_t i) { return samples[i].time; });
  std::vector<double> times;
  for (const std::size_t i : order) times.push_back(samples[i].time);
  const std::size_t stride =
      order.size() / static_cast<std::size_t>(options.max_displacement_tests) + 1;
  // The later scan: detections within half a typical scan interval of the horizon.
  const double half_window = 0.1 * options.displacement_horizon_s;
  const Eigen::Matrix2d radar_from_vehicle = rotation(-model.yaw);
  DisplacementCheck check;
  std::vector<std::size_t> candidates;
  for (std::size_t k = 0; k < order.size(); k += stride) {
    const RadarSample& sample = samples[order[k]];
    const double target = sample.time + options.displacement_horizon_s;
    const auto begin = std::ranges::lower_bound(times, target - half_window);
    const auto end = std::ranges::upper_bound(times, target + half_window);
    if (begin == end) continue;
    const auto first = static_cast<std::size_t>(begin - times.begin());
    const auto last = static_cast<std::size_t>(end - times.begin());
    const Eigen::Vector2d velocity =
        radar_from_vehicle * scaled_radar_velocity(sample, model.speed_scale);
    const Eigen::Vector2d position = position_in_radar(sample);
    const double gate_m =
        options.displacement_gate_m + options.displacement_gate_fraction * sample.range;
    bool matched = false;
    bool mirrored = false;
    for (std::size_t m = first; m < last; ++m) {
      // Each candidate at its own time (scans need not share one stamp).
      const double dt = times[m] - sample.time;
      const Eigen::Vector2d turned = rotation(-sample.yaw_rate * dt) * position;
      const Eigen::Vector2d moved = translation_integral(sample.yaw_rate, dt) * velocity;
      const Eigen::Vector2d seen = position_in_radar(samples[order[m]]);
      matched = matched || (seen - (turned - moved)).norm() <= gate_m;
      mirrored = mirrored || (seen - (turned + moved)).norm() <= gate_m;
    }
    ++check.tests;
    check.matched += matched ? 1 : 0;
    check.mirrored += mirrored ? 1 : 0;
  }
  return check;
}

VelocityChecks check_velocity_fit(const VelocityCheckInputs& inputs,
                                  const RadarVelocityMethodOptions& options) {
  VelocityChecks checks;
  const auto detections = static_cast<double>(inputs.samples.size());
  const auto static_count = static_cast<double>(
      std::count(inputs.static_mask.begin(), inputs.static_mask.end(), std::uint8_t{1}));
  checks.static_fraction = detections > 0.0 ? static_count / detections : 0.0;
  checks.residual_sigma_mps = inputs.residual_sigma_mps;
  checks.residual_sigma_limit_mps =
      std::min(options.max_residual_sigma_ratio * options.nominal_range_rate_sigma_mps,
               options.max_residual_sigma_mps);
  if (checks.residual_sigma_mps > checks.residual_sigma_limit_mps) {
    checks.failures.push_back(fmt::format(
        "the static residuals' robust sigma is {:.3f} m/s, more than {:.3f} m/s ({:g} x the "
        "nominal range-rate noise {:g} m/s, at most {:g} m/s)",
        checks.residual_sigma_mps, checks.residual_sigma_limit_mps,
        options.max_residual_sigma_ratio, options.nominal_range_rate_sigma_mps,
        options.max_residual_sigma_mps));
  }
  if (checks.static_fraction < options.min_static_fraction) {
    checks.failures.push_back(
        fmt::format("only {} of the detections fit the static model (need {})",
                    percent(checks.static_fraction), percent(options.min_static_fraction)));
  }
  const double scale = inputs.model.speed_scale;
  if (scale < options.min_speed_scale || scale > options.max_speed_scale) {
    checks.failures.push_back(fmt::format(
        "the fitted ego-speed scale {:.3f} is outside [{:g}, {:g}]: not a speed error but a wrong "
        "model (azimuth in degrees? range rate of another sign convention?)",
        scale, options.min_speed_scale, options.max_speed_scale));
  }
  if (inputs.at_move_bound) {
    checks.failures.push_back(fmt::format(
        "the refinement ran {:g} deg from the coarse search's optimum (max_refinement_move): the "
        "fit left its basin",
        deg_from_rad(options.max_refinement_move)));
  }
  checks.windows = static_cast<int>(inputs.window_yaws.size());
  if (checks.windows >= options.min_windows_for_agreement) {
    std::vector<double> normalised;
    for (std::size_t i = 0; i < inputs.window_yaws.size(); ++i) {
      normalised.push_back(angle_difference(inputs.window_yaws[i], inputs.model.yaw) /
                           inputs.window_stds[i]);
    }
    checks.window_spread = robust_sigma(normalised);
    if (checks.window_spread > options.max_window_spread) {
      checks.failures.push_back(fmt::format(
          "the {} windows' yaws spread {:.1f} times their standard errors (at most {:g})",
          checks.windows, checks.window_spread, options.max_window_spread));
    }
  }
  checks.displacement =
      check_static_displacement(inputs.samples, inputs.static_mask, inputs.model, options);
  const DisplacementCheck& moved = checks.displacement;
  if (moved.tests >= options.min_displacement_tests && moved.mirrored >= moved.matched) {
    checks.failures.push_back(fmt::format(
        "static targets reappear where the opposite motion would put them ({} of {}), not where "
        "the fitted one does ({}): the range rate's sign is likely flipped",
        moved.mirrored, moved.tests, moved.matched));
  }
  return checks;
}

}  // namespace x2car::radar
