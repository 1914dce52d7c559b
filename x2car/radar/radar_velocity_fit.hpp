// The velocity method's model and its least-squares fit (paper §III-D, eq:radar_vel), written
// with the ego-speed scale s beside the yaw psi:
//   range_rate = -(s v_car + omega x t_V_R) . u(theta + psi),    u(a) = (cos a, sin a),
// v_car = (car speed, 0) the car's own velocity and omega x t_V_R the part the yaw rate adds at the
// radar's lever arm (radar_ego_motion.hpp; the yaw rate comes from the INS attitude, not from its
// speed, so the scale does not touch it). For a car driving straight, range_rate = -s v cos(theta +
// psi): psi moves the cosine along the azimuth, s stretches it, and across a field of view the two
// are separable (sin and cos of the same angle).
// Internal to x2car::radar.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::radar {

struct VelocityModel {
  double yaw = 0.0;          // psi [rad]
  double speed_scale = 1.0;  // s: true speed / the INS speed [-]
};

// Residual measured - predicted range rate [m/s] and its derivatives by psi and s.
struct VelocityResidual {
  double value = 0.0;          // [m/s]
  double d_yaw = 0.0;          // [m/s/rad]
  double d_speed_scale = 0.0;  // [m/s]
};

VelocityResidual velocity_residual(const RadarSample& sample, const VelocityModel& model);

// The radar's velocity over ground in the vehicle frame under the model's speed scale [m/s].
Eigen::Vector2d scaled_radar_velocity(const RadarSample& sample, double speed_scale);

// Huber-weighted Gauss-Newton for psi (and s when `estimate_speed_scale`) on the samples with
// mask[i] != 0 (all when the mask is empty), from `model`. psi stays within `max_move` of
// `anchor_yaw` (the coarse optimum's basin). Returns false when the samples do not constrain the
// parameters (none, or all dead ahead with the scale free).
struct GaussNewtonSettings {
  double huber_width_mps = 0.15;  // [m/s]
  bool estimate_speed_scale = true;
  double anchor_yaw = 0.0;    // [rad]
  double max_move = 0.0;      // [rad]; 0 = unbounded
  double convergence = 1e-7;  // [rad]
  int max_steps = 10;
};

bool gauss_newton_velocity(std::span<const RadarSample> samples, std::span<const std::uint8_t> mask,
                           const GaussNewtonSettings& settings, VelocityModel& model);

// The fit's covariance two ways, at `model`, for the samples with mask[i] != 0:
//   formal: sigma^2 H^-1 with H = sum w J J^T, sigma the robust sigma of the residuals (detections
//           independent);
//   sandwich: H^-1 (B / (B - 1) sum_b g_b g_b^T) H^-1 with g_b = sum_{i in block b} w_i J_i r_i
//   over
//           B time blocks of `block_s` (a detection's error may share its block's: one target seen
//           over seconds, a speed error): the linearised block bootstrap.
struct VelocityCovariance {
  Eigen::Matrix2d formal = Eigen::Matrix2d::Zero();       // (psi, s) [rad^2, rad, 1]
  Eigen::Matrix2d sandwich = Eigen::Matrix2d::Zero();     // idem
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();  // H, unfixed (both parameters)
  double residual_sigma_mps = 0.0;
  int blocks = 0;  // non-empty time blocks
};

VelocityCovariance velocity_covariance(std::span<const RadarSample> samples,
                                       std::span<const std::uint8_t> mask,
                                       const VelocityModel& model, double huber_width_mps,
                                       bool estimate_speed_scale, double block_s);

}  // namespace x2car::radar
