#include "x2car/radar/radar_velocity_method.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "x2car/core/robust_stats.hpp"

namespace x2car::radar {
namespace {

// Residual r = measured - predicted range rate and its derivative dr/dpsi.
struct Residual {
  double value = 0.0;       // [m/s]
  double derivative = 0.0;  // [m/s/rad]
};

Residual residual_at(const RadarSample& sample, double yaw) {
  const double angle = sample.azimuth + yaw;
  const double cos_angle = std::cos(angle);
  const double sin_angle = std::sin(angle);
  const Eigen::Vector2d& v = sample.radar_velocity_in_vehicle;
  // predicted = -(v_x cos + v_y sin) (static_range_rate); d predicted / dpsi = v_x sin - v_y cos.
  return {sample.range_rate + v.x() * cos_angle + v.y() * sin_angle,
          -(v.x() * sin_angle - v.y() * cos_angle)};
}

double huber_weight(double residual, double width) {
  const double magnitude = std::abs(residual);
  return magnitude <= width ? 1.0 : width / magnitude;
}

std::vector<double> selected_residuals(std::span<const RadarSample> samples,
                                       std::span<const std::uint8_t> mask, double yaw) {
  std::vector<double> residuals;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (mask.empty() || mask[i]) residuals.push_back(residual_at(samples[i], yaw).value);
  }
  return residuals;
}

// Gauss-Newton steps with Huber weights on the masked samples: psi += -sum(w J r) / sum(w J^2).
// Returns false when the samples carry no information on psi (all dead ahead, or none).
bool gauss_newton(std::span<const RadarSample> samples, std::span<const std::uint8_t> mask,
                  double huber_width, const RadarVelocityMethodOptions& options, double& yaw,
                  double& information) {
  for (int step = 0; step < 10; ++step) {
    double gradient = 0.0;
    information = 0.0;
    double unweighted_information = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!mask.empty() && !mask[i]) continue;
      const Residual r = residual_at(samples[i], yaw);
      const double weight = huber_weight(r.value, huber_width);
      gradient += weight * r.derivative * r.value;
      information += weight * r.derivative * r.derivative;
      unweighted_information += r.derivative * r.derivative;
    }
    if (!(information > 1e-9) || !std::isfinite(gradient)) return false;
    const double delta = -gradient / information;
    information = unweighted_information;  // for the covariance: sigma^2 / sum J^2
    yaw = wrap_angle(yaw + std::clamp(delta, -0.1, 0.1));
    if (std::abs(delta) < options.convergence) break;
  }
  return true;
}

}  // namespace

double static_range_rate(const RadarSample& sample, double yaw) {
  const double angle = sample.azimuth + yaw;
  const Eigen::Vector2d& v = sample.radar_velocity_in_vehicle;
  return -(v.x() * std::cos(angle) + v.y() * std::sin(angle));
}

CoarseSearch coarse_yaw_search(std::span<const RadarSample> samples,
                               const RadarVelocityMethodOptions& options) {
  CoarseSearch best{.yaw = 0.0, .consistent = -1};
  const int steps = static_cast<int>(std::floor(options.search_half_range / options.search_step));
  for (int k = -steps; k <= steps; ++k) {
    const double yaw = k * options.search_step;
    const auto consistent = std::count_if(samples.begin(), samples.end(), [&](const auto& sample) {
      return std::abs(residual_at(sample, yaw).value) <= options.coarse_tolerance_mps;
    });
    // Ties go to the smaller |yaw| (k runs from -steps, so compare strictly and prefer |k| small).
    if (consistent > best.consistent ||
        (consistent == best.consistent && std::abs(yaw) < std::abs(best.yaw))) {
      best = {yaw, consistent};
    }
  }
  return best;
}

VelocityFit fit_yaw_on(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options) {
  VelocityFit fit;
  fit.yaw = initial_yaw;
  if (samples.size() < 3) return fit;
  const std::vector<double> start = selected_residuals(samples, {}, initial_yaw);
  const double sigma = std::max(robust_sigma(start), 1e-3);
  double information = 0.0;
  if (!gauss_newton(samples, {}, options.huber_sigmas * sigma, options, fit.yaw, information)) {
    return fit;
  }
  const std::vector<double> residuals = selected_residuals(samples, {}, fit.yaw);
  fit.residual_sigma_mps = robust_sigma(residuals);
  fit.formal_std = std::max(fit.residual_sigma_mps, 1e-3) / std::sqrt(information);
  fit.static_count = static_cast<std::int64_t>(samples.size());
  fit.ok = std::isfinite(fit.yaw) && std::isfinite(fit.formal_std);
  return fit;
}

VelocityFit refine_yaw(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options) {
  VelocityFit fit;
  fit.yaw = initial_yaw;
  fit.static_mask.assign(samples.size(), 0);
  double gate = options.coarse_tolerance_mps;
  double information = 0.0;
  for (fit.iterations = 1; fit.iterations <= options.max_iterations; ++fit.iterations) {
    // 1. Static selection under the current psi.
    std::vector<std::uint8_t> mask(samples.size(), 0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      mask[i] = std::abs(residual_at(samples[i], fit.yaw).value) <= gate ? 1 : 0;
    }
    const std::vector<double> residuals = selected_residuals(samples, mask, fit.yaw);
    if (residuals.size() < 3) return fit;
    const double sigma = std::max(robust_sigma(residuals), 1e-3);
    // 2. Robust least squares for psi on the selection.
    const double previous_yaw = fit.yaw;
    if (!gauss_newton(samples, mask, options.huber_sigmas * sigma, options, fit.yaw, information)) {
      return fit;
    }
    const bool same_selection = mask == fit.static_mask;
    fit.static_mask = std::move(mask);
    fit.residual_sigma_mps = sigma;
    gate = std::max(options.gate_sigmas * sigma, options.min_gate_mps);
    if (same_selection && std::abs(angle_difference(fit.yaw, previous_yaw)) < options.convergence) {
      break;
    }
  }
  fit.iterations = std::min(fit.iterations, options.max_iterations);
  fit.static_count = std::count(fit.static_mask.begin(), fit.static_mask.end(), 1);
  fit.formal_std = fit.residual_sigma_mps / std::sqrt(information);
  fit.ok = std::isfinite(fit.yaw) && std::isfinite(fit.formal_std);
  return fit;
}

WindowEstimates window_estimates(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask, double yaw,
                                 const RadarVelocityMethodOptions& options) {
  std::map<std::int64_t, std::vector<RadarSample>> windows;
  const double t0 = samples.front().time;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!static_mask[i]) continue;
    windows[static_cast<std::int64_t>(std::floor((samples[i].time - t0) / options.window_s))]
        .push_back(samples[i]);
  }
  WindowEstimates estimates;
  for (const auto& [index, window] : windows) {
    if (static_cast<int>(window.size()) < options.min_window_points) continue;
    const VelocityFit fit = fit_yaw_on(window, yaw, options);
    if (!fit.ok || !(fit.formal_std > 0.0)) continue;
    estimates.times.push_back(t0 + (static_cast<double>(index) + 0.5) * options.window_s);
    estimates.yaws.push_back(yaw + angle_difference(fit.yaw, yaw));
    estimates.weights.push_back(1.0 / (fit.formal_std * fit.formal_std));
  }
  return estimates;
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
  estimate.fit = refine_yaw(samples, estimate.coarse.yaw, options);
  const VelocityFit& fit = estimate.fit;
  if (!fit.ok || fit.static_count < options.min_static_points) {
    estimate.insufficient_reason =
        fmt::format("only {} detections fit the static-target model; need {}", fit.static_count,
                    options.min_static_points);
    return estimate;
  }
  estimate.windows = window_estimates(samples, fit.static_mask, fit.yaw, options);
  estimate.yaw_std = fit.formal_std;
  const WindowEstimates& windows = estimate.windows;
  if (static_cast<int>(windows.yaws.size()) >= options.min_windows_for_spread) {
    const std::vector<bool> inliers =
        mad_inlier_mask(windows.yaws, {.k = 3.0, .min_sigma = rad_from_deg(0.01)});
    std::vector<double> yaws;
    std::vector<double> weights;
    for (std::size_t i = 0; i < inliers.size(); ++i) {
      if (!inliers[i]) {
        ++estimate.outlier_windows;
        continue;
      }
      yaws.push_back(windows.yaws[i]);
      weights.push_back(windows.weights[i]);
    }
    if (yaws.size() >= 2) {
      estimate.yaw_std = std::max(standard_error_of_weighted_mean(yaws, weights), fit.formal_std);
    }
  }
  return estimate;
}

CalibrationResult velocity_method_result(const RadarVelocityEstimate& estimate) {
  if (estimate.insufficient_reason) {
    CalibrationResult result = insufficient_data("radar", *estimate.insufficient_reason);
    result.method = "velocity";
    return result;
  }
  const VelocityFit& fit = estimate.fit;
  CalibrationResult result;
  result.sensor = "radar";
  result.method = "velocity";
  result.status = CalibrationStatus::kOk;
  result.yaw = fit.yaw;
  result.yaw_std = estimate.yaw_std;
  const auto windows = static_cast<std::int64_t>(estimate.windows.yaws.size());
  result.support = {{"detections", estimate.detections},
                    {"static_detections", fit.static_count},
                    {"windows", windows - estimate.outlier_windows}};
  result.rejections = {{"not_static", estimate.detections - fit.static_count},
                       {"outlier_windows", estimate.outlier_windows}};
  result.diagnostics = {
      {"coarse_yaw_deg", deg_from_rad(estimate.coarse.yaw)},
      {"coarse_consistent_fraction",
       static_cast<double>(estimate.coarse.consistent) / static_cast<double>(estimate.detections)},
      {"fit_yaw_deg", deg_from_rad(fit.yaw)},
      {"fit_formal_std_deg", deg_from_rad(fit.formal_std)},
      {"residual_sigma_mps", fit.residual_sigma_mps},
      {"iterations", fit.iterations}};
  result.series.push_back({"window_yaw", "rad", estimate.windows.times, estimate.windows.yaws});
  return result;
}

}  // namespace x2car::radar
