// GNSS/INS -> car: the mounting yaw by the paper's track-heading method and the pitch by the
// non-holonomic velocity-direction method (DESIGN §2, paper §III-C; core/track_alignment.hpp).
// Roll is not observable from driving alone and is reported as null.
#pragma once

#include <span>
#include <string>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/track_alignment.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::ins {

// Which method's yaw the result reports (both are always computed and kept in the diagnostics).
enum class InsYawMethod {
  // The one with the smaller standard error. With RTK positions they agree to a few thousandths of
  // a degree; with metre-level (SPS) positions the track's heading is noisy and correlated over
  // seconds while the device's Doppler/IMU velocity keeps its direction, so the velocity method
  // wins.
  kAuto,
  kTrackHeading,       // the paper's
  kVelocityDirection,  // non-holonomic
};

// "auto", "track_heading", "velocity_direction"; parsing throws std::invalid_argument otherwise.
const char* to_string(InsYawMethod method);
InsYawMethod ins_yaw_method_from_string(const std::string& text);

struct InsCalibrationOptions {
  InsYawMethod yaw_method = InsYawMethod::kAuto;
  // Spline, gates (v >= 3 m/s, |curvature| <= 0.01 1/m, runs >= 5 s), outlier rejection and
  // standard errors; see core/track_alignment.hpp.
  TrackAlignmentOptions alignment;
  // The velocity method uses the device's own velocity when it reports one (all readers fill it;
  // a log whose velocities are all zero falls back to the spline's).
  bool use_device_velocity = true;
  // The velocity method's yaw is a cross-check of the track-heading yaw: a difference of more than
  // disagreement_sigmas combined standard errors and more than min_disagreement is reported.
  double disagreement_sigmas = 3.0;
  double min_disagreement = rad_from_deg(0.05);  // [rad]
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
