#include "x2car/radar/radar_velocity_method.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/standard_error.hpp"

namespace x2car::radar {
namespace {

// The coarse grid psi_k = first + k step, k = 0 .. size - 1.
struct YawGrid {
  double first = 0.0;  // [rad]
  double step = 0.0;   // [rad]
  int size = 0;
};

YawGrid yaw_grid(const RadarVelocityMethodOptions& options) {
  if (!options.nominal_yaw) {
    const int size = std::max(8, static_cast<int>(std::lround(2.0 * kPi / options.search_step)));
    return {-kPi, 2.0 * kPi / size, size};
  }
  const int half = static_cast<int>(std::floor(options.search_half_range / options.search_step));
  return {*options.nominal_yaw - half * options.search_step, options.search_step, 2 * half + 1};
}

// Adds 1 to the grid values within psi in [from, from + length] (a circular arc).
void add_arc(const YawGrid& grid, double from, double length, std::vector<int>& difference) {
  const double start =
      grid.first + std::fmod(std::fmod(from - grid.first, 2.0 * kPi) + 2.0 * kPi, 2.0 * kPi);
  for (const double shift : {0.0, -2.0 * kPi}) {
    const double a = (start + shift - grid.first) / grid.step;
    const double b = (start + shift + length - grid.first) / grid.step;
    const int k0 = std::max(0, static_cast<int>(std::ceil(a)));
    const int k1 = std::min(grid.size - 1, static_cast<int>(std::floor(b)));
    if (k0 > k1) continue;
    ++difference[static_cast<std::size_t>(k0)];
    --difference[static_cast<std::size_t>(k1) + 1];
  }
}

// How many samples fit the static model at each grid psi under speed scale s.
std::vector<int> consistent_counts(std::span<const RadarSample> samples, const YawGrid& grid,
                                   double speed_scale, double tolerance_mps) {
  std::vector<int> difference(static_cast<std::size_t>(grid.size) + 1, 0);
  for (const RadarSample& sample : samples) {
    const Eigen::Vector2d v = scaled_radar_velocity(sample, speed_scale);
    const double speed = v.norm();
    if (!(speed > 1e-6)) continue;
    // |v| cos(psi + theta - phi) = -r within the tolerance: cos(beta) in [low, high].
    const double c = -sample.range_rate / speed;
    const double low = c - tolerance_mps / speed;
    const double high = c + tolerance_mps / speed;
    if (low > 1.0 || high < -1.0) continue;
    const double beta1 = std::acos(std::min(high, 1.0));
    const double beta2 = std::acos(std::max(low, -1.0));
    const double base = std::atan2(v.y(), v.x()) - sample.azimuth;
    add_arc(grid, base + beta1, beta2 - beta1, difference);
    add_arc(grid, base - beta2, beta2 - beta1, difference);
  }
  std::vector<int> counts(static_cast<std::size_t>(grid.size));
  int running = 0;
  for (std::size_t k = 0; k < counts.size(); ++k) counts[k] = running += difference[k];
  return counts;
}

std::vector<double> speed_scale_grid(const RadarVelocityMethodOptions& options) {
  if (!options.estimate_speed_scale) return {1.0};
  std::vector<double> scales;
  const int steps = static_cast<int>(std::floor(
      (options.max_speed_scale - options.min_speed_scale) / options.coarse_scale_step + 1e-9));
  for (int k = 0; k <= steps; ++k) {
    scales.push_back(options.min_speed_scale + k * options.coarse_scale_step);
  }
  return scales;
}

std::vector<std::uint8_t> static_selection(std::span<const RadarSample> samples,
                                           const VelocityModel& model, double gate_mps) {
  std::vector<std::uint8_t> mask(samples.size(), 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    mask[i] = std::abs(velocity_residual(samples[i], model).value) <= gate_mps ? 1 : 0;
  }
  return mask;
}

std::vector<double> masked_residuals(std::span<const RadarSample> samples,
                                     std::span<const std::uint8_t> mask,
                                     const VelocityModel& model) {
  std::vector<double> residuals;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (mask[i]) residuals.push_back(velocity_residual(samples[i], model).value);
  }
  return residuals;
}

}  // namespace

double static_range_rate(const RadarSample& sample, double yaw, double speed_scale) {
  const double angle = sample.azimuth + yaw;
  const Eigen::Vector2d v = scaled_radar_velocity(sample, speed_scale);
  return -(v.x() * std::cos(angle) + v.y() * std::sin(angle));
}

CoarseSearch coarse_yaw_search(std::span<const RadarSample> samples,
                               const RadarVelocityMethodOptions& options) {
  const YawGrid grid = yaw_grid(options);
  const bool circle = !options.nominal_yaw;
  const double prior = options.nominal_yaw.value_or(0.0);
  CoarseSearch best{.yaw = prior, .speed_scale = 1.0, .consistent = -1};
  const auto better = [&](const CoarseSearch& candidate) {
    if (candidate.consistent != best.consistent) return candidate.consistent > best.consistent;
    const double from_prior = std::abs(angle_difference(candidate.yaw, prior));
    const double best_from_prior = std::abs(angle_difference(best.yaw, prior));
    if (from_prior != best_from_prior) return from_prior < best_from_prior;
    return std::abs(candidate.speed_scale - 1.0) < std::abs(best.speed_scale - 1.0);
  };
  // Every k-th detection: the top of the histogram needs thousands, not all.
  std::vector<RadarSample> thinned;
  const std::size_t stride =
      samples.size() / static_cast<std::size_t>(options.max_coarse_detections) + 1;
  for (std::size_t i = 0; i < samples.size(); i += stride) thinned.push_back(samples[i]);
  for (const double scale : speed_scale_grid(options)) {
    const std::vector<int> counts =
        consistent_counts(thinned, grid, scale, options.coarse_tolerance_mps);
    const int most = *std::max_element(counts.begin(), counts.end());
    // Each run of grid values with the most counts offers its middle: exact data fit over a
    // plateau of psi, and its middle is the best guess.
    const auto at = [&](int k) {
      return counts[static_cast<std::size_t>((k + grid.size) % grid.size)];
    };
    for (int k = 0; k < grid.size; ++k) {
      if (at(k) != most || (circle ? at(k - 1) == most : k > 0 && at(k - 1) == most)) continue;
      int end = k;
      while (end + 1 < k + grid.size && (circle || end + 1 < grid.size) && at(end + 1) == most) {
        ++end;
      }
      const CoarseSearch candidate{wrap_angle(grid.first + 0.5 * (k + end) * grid.step), scale,
                                   most, 0};
      if (better(candidate)) best = candidate;
    }
    if (circle && most == at(-1) &&
        std::all_of(counts.begin(), counts.end(), [&](int count) { return count == most; })) {
      const CoarseSearch candidate{prior, scale, most, 0};  // no information at all
      if (better(candidate)) best = candidate;
    }
  }
  best.counted = static_cast<std::int64_t>(thinned.size());
  return best;
}

VelocityFit refine_yaw(std::span<const RadarSample> samples, const CoarseSearch& coarse,
                       const RadarVelocityMethodOptions& options) {
  VelocityFit fit;
  fit.model = {coarse.yaw, coarse.speed_scale};
  fit.static_mask.assign(samples.size(), 0);
  double gate = options.coarse_tolerance_mps;
  for (fit.iterations = 1; fit.iterations <= options.max_iterations; ++fit.iterations) {
    // 1. Static selection under the current model.
    std::vector<std::uint8_t> mask = static_selection(samples, fit.model, gate);
    const std::vector<double> residuals = masked_residuals(samples, mask, fit.model);
    if (residuals.size() < 3) return fit;
    const double sigma = std::max(robust_sigma(residuals), 1e-3);
    // 2. Robust least squares for (psi, s) on the selection, in the coarse optimum's basin.
    const VelocityModel previous = fit.model;
    const GaussNewtonSettings settings{.huber_width_mps = options.huber_sigmas * sigma,
                                       .estimate_speed_scale = options.estimate_speed_scale,
                                       .anchor_yaw = coarse.yaw,
                                       .max_move = options.max_refinement_move,
                                       .convergence = options.convergence};
    if (!gauss_newton_velocity(samples, mask, settings, fit.model)) return fit;
    const bool same_selection = mask == fit.static_mask;
    fit.static_mask = std::move(mask);
    fit.residual_sigma_mps = sigma;
    gate = std::max(options.gate_sigmas * sigma, options.min_gate_mps);
    if (same_selection &&
        std::abs(angle_difference(fit.model.yaw, previous.yaw)) < options.convergence &&
        std::abs(fit.model.speed_scale - previous.speed_scale) < options.convergence) {
      break;
    }
  }
  fit.iterations = std::min(fit.iterations, options.max_iterations);
  fit.static_count = std::count(fit.static_mask.begin(), fit.static_mask.end(), 1);
  fit.at_move_bound =
      std::abs(angle_difference(fit.model.yaw, coarse.yaw)) >= options.max_refinement_move - 1e-9;
  fit.ok = std::isfinite(fit.model.yaw) && std::isfinite(fit.model.speed_scale);
  return fit;
}

WindowEstimates window_estimates(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask,
                                 const VelocityModel& model, double inflation,
                                 const RadarVelocityMethodOptions& options) {
  std::map<std::int64_t, std::vector<RadarSample>> windows;
  double t0 = INFINITY;
  for (const RadarSample& sample : samples) t0 = std::min(t0, sample.time);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!static_mask[i]) continue;
    windows[static_cast<std::int64_t>(std::floor((samples[i].time - t0) / options.window_s))]
        .push_back(samples[i]);
  }
  WindowEstimates estimates;
  for (const auto& [index, window] : windows) {
    if (static_cast<int>(window.size()) < options.min_window_points) continue;
    VelocityModel window_model = model;
    const std::vector<double> start =
        masked_residuals(window, std::vector<std::uint8_t>(window.size(), 1), window_model);
    const double width = options.huber_sigmas * std::max(robust_sigma(start), 1e-3);
    const GaussNewtonSettings settings{.huber_width_mps = width,
                                       .estimate_speed_scale = options.estimate_speed_scale,
                                       .anchor_yaw = model.yaw,
                                       .max_move = options.max_refinement_move,
                                       .convergence = options.convergence};
    if (!gauss_newton_velocity(window, {}, settings, window_model)) continue;
    const VelocityCovariance covariance = velocity_covariance(
        window, {}, window_model, width, options.estimate_speed_scale, options.block_s);
    const double formal_std = std::sqrt(covariance.formal(0, 0));
    if (!(formal_std > 0.0)) continue;
    estimates.times.push_back(t0 + (static_cast<double>(index) + 0.5) * options.window_s);
    estimates.yaws.push_back(model.yaw + angle_difference(window_model.yaw, model.yaw));
    estimates.stds.push_back(formal_std * inflation);
  }
  return estimates;
}

DopplerEvidence doppler_evidence(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask, double yaw,
                                 std::size_t max_points) {
  const double min_cos = std::cos(rad_from_deg(60.0));
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < samples.size() && i < static_mask.size(); ++i) {
    const Eigen::Vector2d& v = samples[i].radar_velocity_in_vehicle;
    if (static_mask[i] == 0 || v.norm() < 1e-6) continue;
    const double direction = std::atan2(v.y(), v.x());
    if (std::abs(std::cos(samples[i].azimuth + yaw - direction)) >= min_cos) usable.push_back(i);
  }
  DopplerEvidence evidence;
  const std::size_t stride =
      std::max<std::size_t>(1, (usable.size() + max_points - 1) / max_points);
  for (std::size_t k = 0; k < usable.size(); k += stride) {
    const RadarSample& sample = samples[usable[k]];
    const Eigen::Vector2d& v = sample.radar_velocity_in_vehicle;
    const double direction = std::atan2(v.y(), v.x());
    evidence.times.push_back(sample.time);
    evidence.car_speed_mps.push_back(v.norm());
    evidence.implied_speed_mps.push_back(-sample.range_rate /
                                         std::cos(sample.azimuth + yaw - direction));
  }
  return evidence;
}

RadarVelocityEstimate estimate_yaw_by_velocity(std::span<const RadarSample> samples,
                                               double max_speed_mps,
                                               const RadarVelocityMethodOptions& options) {
  RadarVelocityEstimate estimate;
  estimate.detections = static_cast<std::int64_t>(samples.size());
  if (estimate.detections < options.min_static_points) {
    estimate.insufficient_reason = fmt::format(
        "only {} radar detections taken while the car moved straight at >= the "
        "minimum speed (fastest {:.1f} m/s); need {}",
        samples.size(), max_speed_mps, options.min_static_points);
    return estimate;
  }
  estimate.coarse = coarse_yaw_search(samples, options);
  estimate.fit = refine_yaw(samples, estimate.coarse, options);
  const VelocityFit& fit = estimate.fit;
  if (!fit.ok || fit.static_count < options.min_static_points) {
    estimate.insufficient_reason =
        fmt::format("only {} detections fit the static-target model; need {}", fit.static_count,
                    options.min_static_points);
    return estimate;
  }
  estimate.covariance =
      velocity_covariance(samples, fit.static_mask, fit.model,
                          options.huber_sigmas * std::max(fit.residual_sigma_mps, 1e-3),
                          options.estimate_speed_scale, options.block_s);
  const VelocityCovariance& covariance = estimate.covariance;
  if (covariance.blocks < options.min_blocks) {
    estimate.insufficient_reason = fmt::format(
        "the static detections span only {} time blocks of {:g} s; need {} for a standard error",
        covariance.blocks, options.block_s, options.min_blocks);
    return estimate;
  }
  // The standard error: block-clustered, Student-t widened, with the floors.
  const double t_factor = small_sample_factor(covariance.blocks - 1);
  estimate.formal_yaw_std = std::sqrt(covariance.formal(0, 0));
  const double block_yaw_std = std::sqrt(covariance.sandwich(0, 0)) * t_factor;
  // With the scale held at 1, its nominal error moves psi by (dpsi/ds) sigma_s.
  const Eigen::Matrix2d& information = covariance.information;
  const double scale_floor =
      options.estimate_speed_scale
          ? 0.0
          : std::abs(information(0, 1) / information(0, 0)) * options.speed_scale_sigma;
  estimate.yaw_std =
      std::max({block_yaw_std, estimate.formal_yaw_std, scale_floor, options.min_yaw_std});
  estimate.speed_scale_std = options.estimate_speed_scale
                                 ? std::max(std::sqrt(covariance.sandwich(1, 1)) * t_factor,
                                            std::sqrt(covariance.formal(1, 1)))
                                 : 0.0;
  const double inflation =
      std::max(1.0, estimate.yaw_std / std::max(estimate.formal_yaw_std, 1e-12));
  estimate.windows = window_estimates(samples, fit.static_mask, fit.model, inflation, options);
  estimate.doppler = doppler_evidence(samples, fit.static_mask, fit.model.yaw);
  estimate.checks = check_velocity_fit({.samples = samples,
                                        .static_mask = fit.static_mask,
                                        .model = fit.model,
                                        .residual_sigma_mps = fit.residual_sigma_mps,
                                        .at_move_bound = fit.at_move_bound,
                                        .window_yaws = estimate.windows.yaws,
                                        .window_stds = estimate.windows.stds},
                                       options);
  return estimate;
}

CalibrationResult velocity_method_result(const RadarVelocityEstimate& estimate) {
  if (estimate.insufficient_reason) {
    CalibrationResult result = insufficient_data("radar", *estimate.insufficient_reason);
    result.method = "velocity";
    return result;
  }
  const VelocityFit& fit = estimate.fit;
  const VelocityChecks& checks = estimate.checks;
  CalibrationResult result;
  result.sensor = "radar";
  result.method = "velocity";
  result.status = CalibrationStatus::kOk;
  result.yaw = fit.model.yaw;
  result.yaw_std = estimate.yaw_std;
  const auto windows = static_cast<std::int64_t>(estimate.windows.yaws.size());
  result.support = {{"detections", estimate.detections},
                    {"static_detections", fit.static_count},
                    {"windows", windows},
                    {"blocks", estimate.covariance.blocks}};
  result.rejections = {{"not_static", estimate.detections - fit.static_count}};
  result.diagnostics = {
      {"speed_scale", fit.model.speed_scale},
      {"speed_scale_std", estimate.speed_scale_std},
      {"coarse_yaw_deg", deg_from_rad(estimate.coarse.yaw)},
      {"coarse_speed_scale", estimate.coarse.speed_scale},
      {"coarse_consistent_fraction",
       static_cast<double>(estimate.coarse.consistent) /
           static_cast<double>(std::max<std::int64_t>(estimate.coarse.counted, 1))},
      {"fit_formal_std_deg", deg_from_rad(estimate.formal_yaw_std)},
      {"residual_sigma_mps", fit.residual_sigma_mps},
      {"residual_sigma_limit_mps", checks.residual_sigma_limit_mps},
      {"static_fraction", checks.static_fraction},
      {"window_spread", checks.window_spread},
      {"displacement_tests", static_cast<double>(checks.displacement.tests)},
      {"displacement_matched", static_cast<double>(checks.displacement.matched)},
      {"displacement_mirrored", static_cast<double>(checks.displacement.mirrored)},
      {"iterations", fit.iterations}};
  result.series.push_back({"window_yaw", "rad", estimate.windows.times, estimate.windows.yaws});
  result.series.push_back(
      {"doppler_car_speed", "m/s", estimate.doppler.times, estimate.doppler.car_speed_mps});
  result.series.push_back(
      {"doppler_implied_speed", "m/s", estimate.doppler.times, estimate.doppler.implied_speed_mps});
  if (!checks.passed()) {
    std::string reason = "velocity method: the fit fails its checks: ";
    for (std::size_t i = 0; i < checks.failures.size(); ++i) {
      reason += (i == 0 ? "" : "; ") + checks.failures[i];
    }
    return mark_unreliable(std::move(result), std::move(reason));
  }
  return result;
}

}  // namespace x2car::radar
