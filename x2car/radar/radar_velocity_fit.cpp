#include "x2car/radar/radar_velocity_fit.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::radar {
namespace {

double huber_weight(double residual, double width) {
  const double magnitude = std::abs(residual);
  return magnitude <= width ? 1.0 : width / magnitude;
}

bool selected(std::span<const std::uint8_t> mask, std::size_t i) { return mask.empty() || mask[i]; }

// The normal equations with the scale held when it is not estimated.
Eigen::Matrix2d held_information(Eigen::Matrix2d information, bool estimate_speed_scale) {
  if (!estimate_speed_scale) {
    information(0, 1) = information(1, 0) = 0.0;
    information(1, 1) = 1.0;
  }
  return information;
}

Eigen::Matrix2d inverse_or_zero(const Eigen::Matrix2d& matrix, bool estimate_speed_scale) {
  Eigen::Matrix2d inverse = matrix.inverse();
  if (!estimate_speed_scale) inverse(1, 1) = 0.0;
  return inverse.allFinite() ? inverse : Eigen::Matrix2d::Zero();
}

}  // namespace

Eigen::Vector2d scaled_radar_velocity(const RadarSample& sample, double speed_scale) {
  const Eigen::Vector2d car(sample.car_speed_mps, 0.0);
  return sample.radar_velocity_in_vehicle + (speed_scale - 1.0) * car;
}

VelocityResidual velocity_residual(const RadarSample& sample, const VelocityModel& model) {
  const double angle = sample.azimuth + model.yaw;
  const double cos_angle = std::cos(angle);
  const double sin_angle = std::sin(angle);
  const Eigen::Vector2d v = scaled_radar_velocity(sample, model.speed_scale);
  // predicted = -(v_x cos + v_y sin); r = measured - predicted.
  return {sample.range_rate + v.x() * cos_angle + v.y() * sin_angle,
          -v.x() * sin_angle + v.y() * cos_angle, sample.car_speed_mps * cos_angle};
}

bool gauss_newton_velocity(std::span<const RadarSample> samples, std::span<const std::uint8_t> mask,
                           const GaussNewtonSettings& settings, VelocityModel& model) {
  for (int step = 0; step < settings.max_steps; ++step) {
    Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!selected(mask, i)) continue;
      const VelocityResidual r = velocity_residual(samples[i], model);
      const Eigen::Vector2d jacobian(r.d_yaw, r.d_speed_scale);
      const double weight = huber_weight(r.value, settings.huber_width_mps);
      information += weight * jacobian * jacobian.transpose();
      gradient += weight * r.value * jacobian;
    }
    if (!settings.estimate_speed_scale) gradient(1) = 0.0;
    const Eigen::Matrix2d held = held_information(information, settings.estimate_speed_scale);
    // Too little information on psi or s (relative to their scales) is no fit.
    if (!(held(0, 0) > 1e-9) || !(held.determinant() > 1e-12 * held(0, 0) * held(1, 1)) ||
        !gradient.allFinite()) {
      return false;
    }
    const Eigen::Vector2d delta = -held.ldlt().solve(gradient);
    double yaw = model.yaw + std::clamp(delta(0), -0.1, 0.1);
    if (settings.max_move > 0.0) {
      const double move = angle_difference(yaw, settings.anchor_yaw);
      yaw = settings.anchor_yaw + std::clamp(move, -settings.max_move, settings.max_move);
    }
    model.yaw = wrap_angle(yaw);
    model.speed_scale += std::clamp(delta(1), -0.05, 0.05);
    if (std::abs(delta(0)) < settings.convergence && std::abs(delta(1)) < settings.convergence) {
      break;
    }
  }
  return std::isfinite(model.yaw) && std::isfinite(model.speed_scale);
}

VelocityCovariance velocity_covariance(std::span<const RadarSample> samples,
                                       std::span<const std::uint8_t> mask,
                                       const VelocityModel& model, double huber_width_mps,
                                       bool estimate_speed_scale, double block_s) {
  VelocityCovariance covariance;
  std::vector<double> residuals;
  std::map<std::int64_t, Eigen::Vector2d> block_gradients;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!selected(mask, i)) continue;
    const VelocityResidual r = velocity_residual(samples[i], model);
    const Eigen::Vector2d jacobian(r.d_yaw, estimate_speed_scale ? r.d_speed_scale : 0.0);
    const double weight = huber_weight(r.value, huber_width_mps);
    covariance.information += weight * Eigen::Vector2d(r.d_yaw, r.d_speed_scale) *
                              Eigen::Vector2d(r.d_yaw, r.d_speed_scale).transpose();
    const auto block = static_cast<std::int64_t>(std::floor(samples[i].time / block_s));
    auto [entry, inserted] = block_gradients.try_emplace(block, Eigen::Vector2d::Zero());
    entry->second += weight * r.value * jacobian;
    residuals.push_back(r.value);
  }
  if (residuals.size() < 3) return covariance;
  covariance.residual_sigma_mps = robust_sigma(residuals);
  const Eigen::Matrix2d inverse = inverse_or_zero(
      held_information(covariance.information, estimate_speed_scale), estimate_speed_scale);
  const double sigma = std::max(covariance.residual_sigma_mps, 1e-3);
  covariance.formal = sigma * sigma * inverse;
  covariance.blocks = static_cast<int>(block_gradients.size());
  if (covariance.blocks >= 2) {
    Eigen::Matrix2d meat = Eigen::Matrix2d::Zero();
    for (const auto& [block, gradient] : block_gradients) meat += gradient * gradient.transpose();
    meat *= static_cast<double>(covariance.blocks) / (covariance.blocks - 1);
    covariance.sandwich = inverse * meat * inverse;
  }
  return covariance;
}

}  // namespace x2car::radar
