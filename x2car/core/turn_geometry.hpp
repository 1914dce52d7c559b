// What a turn does to a sensor's track (issue 12, "use the turns"; beyond the paper, which keeps
// only nearly straight samples, §III-B/C).
//
// The car's reference point, the rear axle (the origin of V, DESIGN §1), moves along the car's x
// axis: a car rolling on its tyres has no lateral velocity there (kinematic bicycle; the sideslip
// of real tyres grows with the lateral acceleration and is kept small by gating on it). A sensor at
// the lever arm r = (r_x, r_y, r_z) in V moves with
//   v_sensor = v_car + omega x r = (v - omega r_y, omega r_x, 0)   in V,
// omega the yaw rate, so its velocity, and the tangent of its track, point
//   beta = asin(omega r_x / s) = asin(kappa r_x),   kappa = omega / s,
// to the left of the car's x axis, s = |v_sensor| the sensor's own speed (what its track gives).
// Both yaws of core/track_alignment.hpp then see, per sample,
//   offset = wrap(sensor yaw - track heading) = psi - beta,
// psi the mounting yaw. Only r_x enters: r_y changes the sensor's speed, not its direction.
// With r_x known, beta is added back; without it, r_x and psi are fitted jointly (the lateral
// velocity of the sensor in the car's frame is omega r_x: the offsets fall linearly with kappa,
// slope -r_x), which needs kappa to vary over the samples (straights and turns): on a circle psi
// and r_x cannot be told apart.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "x2car/core/segmentation.hpp"

namespace x2car {

// beta_i = asin(kappa_i r_x) per sample [rad] (kappa clamped so that |kappa r_x| <= 1; NaN kappa
// gives NaN). `yaw_rate_curvature` [1/m] is the yaw rate over the sensor's speed, `lever_arm_x` [m]
// the sensor's x in the vehicle frame (ahead of the rear axle: > 0).
std::vector<double> lever_arm_heading_shift(std::span<const double> yaw_rate_curvature,
                                            double lever_arm_x);

struct LeverArmFitOptions {
  // Samples whose residual is more than k robust sigmas (at least min_sigma [rad]) off are left
  // out.
  double outlier_k = 3.0;
  double outlier_min_sigma = 1e-4;  // [rad] (0.006 deg)
  // Samples closer in time than this share their errors (track noise, smoothing): the standard
  // error of r_x counts one sample per correlation_s of valid driving [s].
  double correlation_s = 1.0;

  void Check() const;
};

struct LeverArmFit {
  double lever_arm_x = 0.0;  // [m]
  // [m]; infinite when kappa does not vary over the samples (r_x not identifiable).
  double lever_arm_x_std = std::numeric_limits<double>::infinity();
  double yaw = 0.0;               // the intercept psi [rad]
  double residual_sigma = 0.0;    // of the inliers [rad]
  double mean_curvature = 0.0;    // mean kappa of the inliers [1/m]
  double curvature_spread = 0.0;  // standard deviation of kappa over the inliers [1/m]
  std::int64_t samples = 0;       // inliers used
  std::int64_t outliers = 0;
};

// Least squares (Gauss-Newton) of offset_i = psi - asin(kappa_i r_x) over the samples inside
// `segments` with finite values, with median/MAD outlier rejection of the residuals. `offsets`
// [rad] are wrapped angles near one value. Fewer than 3 usable samples give the zero fit with an
// infinite standard error.
LeverArmFit fit_lever_arm_x(std::span<const double> offsets,
                            std::span<const double> yaw_rate_curvature,
                            const Segmentation& segments, const LeverArmFitOptions& options = {});

}  // namespace x2car
