// The radar velocity method (radar_calibration.hpp; paper §III-D, eq:radar_vel): for a static
// target the range rate is the radar's own velocity projected on the line of sight,
//   v^R_i = v^G_i cos(theta^R_i + psi)                                          (eq:radar_vel)
// (here with the sign of d range / dt and the radar's full 2-D velocity, static_range_rate). The
// steps: the coarse grid search over [-A, A] ("Course Calibration"), the iterated static selection
// and robust fit ("Refined Calibration"), per-window fits for the standard error, and the estimate
// written as a result. Internal to x2car::radar.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::radar {

// eq:radar_vel: the range rate [m/s] a static target at radar azimuth `sample.azimuth` would have
// for radar yaw `yaw` [rad]: -(v_x cos(theta + psi) + v_y sin(theta + psi)).
double static_range_rate(const RadarSample& sample, double yaw);

struct CoarseSearch {
  double yaw = 0.0;             // grid value with the most consistent detections [rad]
  std::int64_t consistent = 0;  // how many
};

// "Course Calibration": psi on the grid -A, -A + n, ..., A with the most detections within
// coarse_tolerance_mps of eq:radar_vel (the static objects are assumed the majority).
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

// "Refined Calibration": iterates the static selection by eq:radar_vel and a Huber-weighted
// Gauss-Newton fit of the cosine from `initial_yaw`.
VelocityFit refine_yaw(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options);

// Gauss-Newton fit on the given (static) samples only, no reselection; ok = false when the
// samples do not constrain psi.
VelocityFit fit_yaw_on(std::span<const RadarSample> samples, double initial_yaw,
                       const RadarVelocityMethodOptions& options);

// Per-window fits on the static detections, starting from the global psi.
struct WindowEstimates {
  std::vector<double> times;    // window centres [s]
  std::vector<double> yaws;     // [rad]
  std::vector<double> weights;  // 1 / formal variance [1/rad^2]
};

WindowEstimates window_estimates(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask, double yaw,
                                 const RadarVelocityMethodOptions& options);

// The velocity method's typed estimate: the global fit is the yaw (it weighs every detection by
// its information); the windows' inverse-variance weighted spread, never below the fit's formal
// error, is its standard error when there are enough windows (outlier windows rejected by MAD).
struct RadarVelocityEstimate {
  std::optional<std::string> insufficient_reason;  // set: the fields below are partial
  std::int64_t detections = 0;                     // gated detections offered to the method
  CoarseSearch coarse;
  VelocityFit fit;
  WindowEstimates windows;
  std::int64_t outlier_windows = 0;
  double yaw_std = 0.0;  // [rad]
};

// The whole method on the gated samples (time order); `max_speed_mps` (the fastest car speed seen)
// only words the reason when there are too few.
RadarVelocityEstimate estimate_yaw_by_velocity(std::span<const RadarSample> samples,
                                               double max_speed_mps,
                                               const RadarVelocityMethodOptions& options);

// The estimate as a result with method "velocity": yaw, yaw_std, support (detections,
// static_detections, windows), rejections (not_static, outlier_windows), diagnostics
// (coarse_yaw_deg, coarse_consistent_fraction, fit_yaw_deg, fit_formal_std_deg,
// residual_sigma_mps, iterations) and the window_yaw series; or insufficient data with the reason.
CalibrationResult velocity_method_result(const RadarVelocityEstimate& estimate);

}  // namespace x2car::radar
