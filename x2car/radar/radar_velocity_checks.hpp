// The velocity method's checks of its own fit (docs/methods.md, "Checks"): a fit that fails one is
// reported `unreliable` with the reason, never `ok`. Each check answers a way the method has been
// seen to go wrong on real logs:
//   residual spread   the static residuals' robust sigma against the radar's nominal range-rate
//                     noise (a wrong yaw or a wrong model leaves residuals of m/s, not 0.1 m/s);
//   static fraction   too few detections fit the static model (azimuth in degrees);
//   speed scale       s outside [min, max]: not a speed error but a wrong model;
//   basin             the refinement ran to max_refinement_move from the coarse optimum;
//   windows           the per-window yaws disagree beyond their standard errors;
//   displacement      static targets do not reappear where the fitted motion moves them, but where
//                     the opposite motion would: a flipped range-rate sign fits the cosine at
//                     psi + 180 deg exactly, and only the positions tell.
// Internal to x2car::radar.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_velocity_fit.hpp"

namespace x2car::radar {

// Static detections sought again displacement_horizon_s later: `tests` had a later scan to look
// in; `matched` were found where the fitted motion predicts them, `mirrored` where the opposite
// translation would put them.
struct DisplacementCheck {
  std::int64_t tests = 0;
  std::int64_t matched = 0;
  std::int64_t mirrored = 0;
};

// A static target at p (radar frame) seen from a radar moving with velocity a (radar frame, the
// model's) while the car turns at omega moves as dp/dt = -a - omega x p, hence after dt
//   p(dt) = R(-omega dt) p - M(dt) a,   M(dt) = integral_0^dt R(-omega u) du.
// `samples` sorted by time or not; the mask selects the static detections.
DisplacementCheck check_static_displacement(std::span<const RadarSample> samples,
                                            std::span<const std::uint8_t> static_mask,
                                            const VelocityModel& model,
                                            const RadarVelocityMethodOptions& options);

struct VelocityChecks {
  double residual_sigma_mps = 0.0;
  double residual_sigma_limit_mps = 0.0;
  double static_fraction = 0.0;
  double window_spread = 0.0;  // robust sigma of (window psi - psi) / window SE; 0 if unchecked
  int windows = 0;
  DisplacementCheck displacement;
  std::vector<std::string> failures;  // one per failed check, with its figures

  bool passed() const { return failures.empty(); }
};

struct VelocityCheckInputs {
  std::span<const RadarSample> samples;
  std::span<const std::uint8_t> static_mask;
  VelocityModel model;
  double residual_sigma_mps = 0.0;
  bool at_move_bound = false;
  std::span<const double> window_yaws;  // [rad]
  std::span<const double> window_stds;  // [rad]
};

VelocityChecks check_velocity_fit(const VelocityCheckInputs& inputs,
                                  const RadarVelocityMethodOptions& options);

}  // namespace x2car::radar
