// GNSS/INS -> car: the mounting yaw by the paper's track-heading method and the pitch by the
// non-holonomic velocity-direction method (DESIGN §2, paper §III-C; core/track_alignment.hpp).
// Roll is not observable from driving alone and is reported as null.
#pragma once

#include <span>
#include <string>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/track_alignment.hpp"
#include "x2car/core/yaw_choice.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::ins {

// The device's own attitude errors that stay put over a drive (a heading bias of the GNSS/INS
// solution, a levelling error): they pass straight into the mounting angles, and no spread of the
// data shows them, so they are added in quadrature to the standard errors (docs/methods.md,
// "Standard errors"). The defaults are what survey-grade RTK GNSS/INS units specify (1 sigma,
// heading 0.02-0.05 deg, roll and pitch 0.005-0.02 deg); set them from the device's datasheet: a
// MEMS unit with single-antenna heading is 0.1-0.5 deg. 0 turns the floor off.
struct DeviceAttitudeBias {
  double heading = rad_from_deg(0.03);  // [rad], 1 sigma
  double pitch = rad_from_deg(0.01);    // [rad], 1 sigma

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct InsCalibrationOptions {
  // Which yaw the result reports (both are always computed and kept in the diagnostics); auto
  // takes the smaller standard error. With SPS positions that is the velocity direction.
  YawMethod yaw_method = YawMethod::kAuto;
  // Spline, gates (v >= 3 m/s, |curvature| <= 0.01 1/m, runs >= 5 s), outlier rejection and
  // standard errors; see core/track_alignment.hpp.
  TrackAlignmentOptions alignment;
  // The velocity method uses the device's own velocity when it reports one (all readers fill it;
  // a log whose velocities are all zero falls back to the spline's).
  bool use_device_velocity = true;
  // The velocity method's yaw is a cross-check of the track-heading yaw: a disagreement is
  // reported in `reason`.
  DisagreementTest disagreement;
  // Floor of the yaw's and pitch's standard errors (both yaw methods share the heading bias).
  DeviceAttitudeBias device_bias;
  bool keep_series = true;  // per-sample series for the report (large for long logs)

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// `records` in time order (the readers guarantee strictly increasing times). Returns an ok result,
// or insufficient_data with a reason that says what is missing; never NaN angles. Throws
// std::invalid_argument only on invalid options.
CalibrationResult calibrate_ins(std::span<const io::InsRecord> records,
                                const InsCalibrationOptions& options = {});

}  // namespace x2car::ins
