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
