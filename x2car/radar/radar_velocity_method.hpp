// The velocity method's steps (radar_calibration.hpp; paper §III-D, Eq. for v_r): the static
// target model, the coarse grid search and the robust refinement. Internal to x2car::radar.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::radar {

// Range rate [m/s] a static target at radar azimuth `sample.azimuth` would have for radar yaw
// `yaw` [rad]: -(v_x cos(theta + psi) + v_y sin(theta + psi)).
double static_range_rate(const RadarSample& sample, double yaw);

struct CoarseSearch {
  double yaw = 0.0;             // grid value with the most consistent detections [rad]
  std::int64_t consistent = 0;  // how many
};

CoarseSearch coarse_yaw_search(std::span<const RadarSample> samples,
                               const RadarVelocityMethodOptions& options);

struct VelocityFit {
  bool ok = false;
  double yaw = 0.0;                 // [rad]
  double formal_std = 0.0;          // least-squares standard error [rad]
  double residual_sigma_mps = 0.0;  // robust sigma of the selected residuals [m/s]
  int iterations = 0;
  std::vector<std::uint8_t> static_mask;  // per sample: 1 = selected as static
  std::int64_t static_count = 0;
};

// Iterates static selection and a Huber-weighted Gauss-Newton fit from `initial_yaw`.
VelocityFit refine_yaw(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options);

// Gauss-Newton fit on the given (static) samples only, no reselection; ok = false when the
// samples do not constrain psi.
VelocityFit fit_yaw_on(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options);

}  // namespace x2car::radar
