// The radar velocity method (radar_calibration.hpp; paper §III-D, eq:radar_vel): for a static
// target the range rate is the radar's own velocity projected on the line of sight,
//   v^R_i = v^G_i cos(theta^R_i + psi)                                          (eq:radar_vel)
// (here with the sign of d range / dt, the radar's full 2-D velocity and the ego-speed scale s,
// radar_velocity_fit.hpp). The steps: the coarse search over the full circle or around a prior
// ("Course Calibration"), the iterated static selection and robust fit of (psi, s) ("Refined
// Calibration"), the block-clustered standard error, per-window fits, the checks of the fit
// (radar_velocity_checks.hpp), and the estimate written as a result. Internal to x2car::radar.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_velocity_checks.hpp"
#include "x2car/radar/radar_velocity_fit.hpp"

namespace x2car::radar {

// eq:radar_vel: the range rate [m/s] a static target at radar azimuth `sample.azimuth` would have
// for radar yaw `yaw` [rad] and ego-speed scale `speed_scale`: -(v_x cos(theta + psi) + v_y
// sin(theta + psi)) with v the radar's velocity under that scale.
double static_range_rate(const RadarSample& sample, double yaw, double speed_scale = 1.0);

struct CoarseSearch {
  double yaw = 0.0;             // grid value with the most consistent detections [rad]
  double speed_scale = 1.0;     // the scale it was found at [-]
  std::int64_t consistent = 0;  // how many
  std::int64_t counted = 0;     // of how many (every k-th detection, max_coarse_detections)
};

// "Course Calibration": psi on a grid of search_step over the full circle (or nominal_yaw +- A),
// and s over [min_speed_scale, max_speed_scale] in coarse_scale_step (s = 1 alone when it is not
// estimated): the grid value with the most detections within coarse_tolerance_mps of eq:radar_vel
// wins (the static targets are assumed the largest consistent group); ties go to the value nearest
// the prior (nominal_yaw, else 0) and s nearest 1. Each detection adds 1 to the arcs of psi where
// it fits (two arcs: psi = phi +- acos(-r / |v|) - theta), so all grid values cost O(n + grid).
CoarseSearch coarse_yaw_search(std::span<const RadarSample> samples,
                               const RadarVelocityMethodOptions& options);

struct VelocityFit {
  bool ok = false;
  VelocityModel model;
  double residual_sigma_mps = 0.0;  // robust sigma of the selected residuals [m/s]
  int iterations = 0;
  bool at_move_bound = false;             // psi ended max_refinement_move from the coarse optimum
  std::vector<std::uint8_t> static_mask;  // per sample: 1 = selected as static
  std::int64_t static_count = 0;
};

// "Refined Calibration": iterates the static selection by eq:radar_vel and a Huber-weighted
// Gauss-Newton fit of (psi, s) from the coarse optimum, psi kept within max_refinement_move of it.
VelocityFit refine_yaw(std::span<const RadarSample> samples, const CoarseSearch& coarse,
                       const RadarVelocityMethodOptions& options);

// Per-window fits on the static detections, starting from the global model; each window's
// standard error is its least-squares one times the global fit's inflation (sandwich / formal).
struct WindowEstimates {
  std::vector<double> times;  // window centres [s]
  std::vector<double> yaws;   // [rad]
  std::vector<double> stds;   // [rad]
};

WindowEstimates window_estimates(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask,
                                 const VelocityModel& model, double inflation,
                                 const RadarVelocityMethodOptions& options);

// The paper's Fig. 9, for plots: static detections as the car's speed at the radar |v| [m/s] and
// the speed their range rate implies along the motion, -v_r / cos(theta + psi - phi) [m/s] (phi:
// the direction of v in the car), which lies on the line through the origin with slope s (the
// speed scale) when the yaw psi is right. An even subsample of at most max_points; detections
// within 60 deg of perpendicular to the motion are left out (the cosine would divide by ~0).
struct DopplerEvidence {
  std::vector<double> times;              // [s]
  std::vector<double> car_speed_mps;      // |v| at the radar, from the GNSS/INS
  std::vector<double> implied_speed_mps;  // -v_r / cos(theta + psi - phi)
};

DopplerEvidence doppler_evidence(std::span<const RadarSample> samples,
                                 std::span<const std::uint8_t> static_mask, double yaw,
                                 std::size_t max_points = 3000);

// The velocity method's typed estimate: the global fit is the yaw (it weighs every detection by
// its information); its standard error the block-clustered one (radar_velocity_fit.hpp), never
// below the least-squares one or the floors.
struct RadarVelocityEstimate {
  std::optional<std::string> insufficient_reason;  // set: the fields below are partial
  std::int64_t detections = 0;                     // gated detections offered to the method
  CoarseSearch coarse;
  VelocityFit fit;
  VelocityCovariance covariance;
  WindowEstimates windows;
  double yaw_std = 0.0;          // [rad]
  double speed_scale_std = 0.0;  // [-]; 0 when not estimated
  double formal_yaw_std = 0.0;   // least-squares [rad]
  VelocityChecks checks;
  DopplerEvidence doppler;
};

// The whole method on the gated samples; `max_speed_mps` (the fastest car speed seen) only words
// the reason when there are too few.
RadarVelocityEstimate estimate_yaw_by_velocity(std::span<const RadarSample> samples,
                                               double max_speed_mps,
                                               const RadarVelocityMethodOptions& options);

// The estimate as a result with method "velocity": yaw, yaw_std, support (detections,
// static_detections, windows, blocks), rejections (not_static), diagnostics (speed_scale,
// speed_scale_std, coarse_yaw_deg, coarse_consistent_fraction, fit_formal_std_deg,
// residual_sigma_mps, static_fraction, the checks' figures), the window_yaw series and the
// Doppler evidence (doppler_car_speed, doppler_implied_speed); status
// unreliable with the failed checks, or insufficient data with the reason.
CalibrationResult velocity_method_result(const RadarVelocityEstimate& estimate);

}  // namespace x2car::radar
