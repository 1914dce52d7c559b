// --method auto (radar_calibration.hpp): both methods' results, one reported, with the reason.
// Internal to x2car::radar.
//
// Rule (docs/methods.md):
//   - both ok and agreeing, |psi_v - psi_p| <= agreement_sigmas * sqrt(se_v^2 + se_p^2) +
//     agreement_floor: the one with the smaller standard error;
//   - both ok and disagreeing: the position method when at least min_position_objects static
//     objects support it (the Doppler is the suspect: noisy or biased range rates, an ego-speed
//     scale error or a time offset bias the velocity method but not the triangles), otherwise the
//     velocity method;
//     and when they are more than max_disagreement apart, that result marked unreliable;
//   - one ok: that one, with the other's status and reason;
//   - neither: unreliable when either failed its checks (its figures kept), else insufficient data,
//     with both reasons.
// The reported result keeps its own fields; both methods' yaw, standard error and support are added
// to diagnostics ("velocity_yaw_deg", ...) and support ("velocity_static_detections", ...), and
// `reason` says which was chosen and why.
#pragma once

#include "x2car/core/calibration_result.hpp"
#include "x2car/radar/radar_calibration.hpp"

namespace x2car::radar {

CalibrationResult choose_radar_method(CalibrationResult velocity, CalibrationResult position,
                                      const RadarAutoOptions& options);

}  // namespace x2car::radar
