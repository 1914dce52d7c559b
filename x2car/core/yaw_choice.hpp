// Which of a track alignment's two yaws a calibrator reports (core/track_alignment.hpp: the
// paper's track heading and the non-holonomic velocity direction), and the figures that let a
// reader compare them. Shared by the GNSS/INS and LiDAR calibrators.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/track_alignment.hpp"

namespace x2car {

enum class YawMethod {
  // The one with the smaller standard error. With precise positions the two agree to a few
  // thousandths of a degree; with metre-level GNSS positions the track's heading is noisy and
  // correlated over seconds while a device's Doppler/IMU velocity keeps its direction.
  kAuto,
  kTrackHeading,       // the paper's
  kVelocityDirection,  // non-holonomic
};

// "auto", "track_heading", "velocity_direction" (one table in yaw_choice.cpp); parsing throws
// std::invalid_argument listing the valid names.
const char* to_string(YawMethod method);
YawMethod yaw_method_from_string(const std::string& text);
std::vector<std::string> yaw_method_names();  // for the CLI's choices

// Two estimates of one angle disagree when they differ by more than `sigmas` combined standard
// errors and by more than `min_difference`.
struct DisagreementTest {
  double sigmas = 3.0;
  double min_difference = rad_from_deg(0.05);  // [rad]

  bool operator()(double a, double a_std, double b, double b_std) const;
  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The yaw `method` picks from an alignment that holds its estimates (no insufficient_reason; throws
// std::invalid_argument otherwise), with both methods' estimates for the cross-check. The pointers
// point into `alignment`.
struct YawChoice {
  YawMethod method = YawMethod::kTrackHeading;  // the one reported: track or velocity direction
  const SegmentAverage* reported = nullptr;
  const SegmentAverage* track_heading = nullptr;       // the paper's (eq:IMU_angle)
  const SegmentAverage* velocity_direction = nullptr;  // non-holonomic
  double difference = 0.0;  // wrap(velocity-direction yaw - track-heading yaw) [rad]
  // A sentence for `reason` when the two disagree beyond the test.
  std::optional<std::string> disagreement;
};
YawChoice choose_yaw(const TrackAlignment& alignment, YawMethod method,
                     const DisagreementTest& disagreement);

// Sets result.yaw, yaw_std and method ("track_heading" or "velocity_direction") from the choice,
// and the diagnostics track_method_yaw_deg, track_method_yaw_std_deg, velocity_method_yaw_deg,
// velocity_method_yaw_std_deg and yaw_disagreement_deg.
void write_yaw_choice(const YawChoice& choice, CalibrationResult& result);

}  // namespace x2car
