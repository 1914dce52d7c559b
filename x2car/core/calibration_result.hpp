// The one result type every calibrator returns (DESIGN §2, §6): the angles it could observe, their
// standard errors, the evidence behind them and, when it failed, why.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car {

enum class CalibrationStatus {
  kOk,                // every observable angle was estimated
  kInsufficientData,  // too little usable data; `reason` says what is missing
  // The method ran but its own checks of the fit failed (residual spread against the sensor's
  // nominal noise, disagreement between windows, impossible speeds: docs/methods.md, "Checks");
  // `reason` says which. The angles may be kept for inspection but are not a mounting.
  kUnreliable,
};

const char* to_string(CalibrationStatus status);
// Parses "ok" / "insufficient_data" / "unreliable"; throws std::invalid_argument otherwise.
CalibrationStatus calibration_status_from_string(const std::string& text);

// The mounting a log's own transforms gave before calibrating (a bag's tf_static: issue 17), shown
// beside the calibrated one as "before -> after".
struct MountingPrior {
  std::string parent;  // e.g. "base_link"
  std::string child;   // the sensor's frame, e.g. "velodyne" (camera: its body frame)
  std::string source;  // where it came from, e.g. "run.bag /tf_static"
  EulerAngles angles;  // of parent_from_child [rad]
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // [m]
};

// A per-sample series kept for plots, e.g. track heading and device yaw over time.
struct Series {
  std::string name;           // e.g. "track_heading"
  std::string unit;           // e.g. "rad", "m", "1/m"
  std::vector<double> time;   // [s] on the log's clock; empty when the series is indexed
  std::vector<double> value;  // same length as `time` (or any length when `time` is empty)
};

struct CalibrationResult {
  std::string sensor;  // "ins", "lidar", "radar", "camera"
  std::string method;  // e.g. "track_heading", "velocity", "position"; empty when there is one
  CalibrationStatus status = CalibrationStatus::kInsufficientData;
  std::string reason;  // why the status is not ok, or a note on how the result was chosen

  // Mounting angles of vehicle_from_sensor [rad]; absent when the method cannot observe them.
  std::optional<double> roll;
  std::optional<double> pitch;
  std::optional<double> yaw;
  // Translation parts of vehicle_from_sensor [m] that the method knows (LiDAR: z).
  std::optional<double> x;
  std::optional<double> y;
  std::optional<double> z;

  // Standard error of each estimated angle [rad] and of z [m].
  std::optional<double> roll_std;
  std::optional<double> pitch_std;
  std::optional<double> yaw_std;
  std::optional<double> z_std;

  // What supported the estimate, e.g. {"samples": 5210, "segments": 7}.
  std::map<std::string, std::int64_t> support;
  // What was left out and why, e.g. {"slow": 1200, "curved": 830, "outlier": 12}.
  std::map<std::string, std::int64_t> rejections;
  // Figures that back or qualify the estimate, each named with its unit, e.g.
  // {"velocity_method_yaw_deg": 2.013, "track_residual_std_m": 0.021}.
  std::map<std::string, double> diagnostics;
  std::vector<Series> series;
  std::optional<MountingPrior> prior;  // when the input carried one

  // Wall time the calibration took [s]; the one field that differs between identical runs
  // (io::ResultJsonOptions::include_timing leaves it out of the JSON).
  double seconds = 0.0;

  bool ok() const { return status == CalibrationStatus::kOk; }
  // The estimated angles with unobserved ones as 0; only meaningful when ok().
  EulerAngles angles_or_zero() const;
};

// A result that says why it could not be computed.
CalibrationResult insufficient_data(std::string sensor, std::string reason);

// Marks `result` unreliable with `reason` (the failed check and its figures), keeping its angles
// and evidence for inspection.
CalibrationResult mark_unreliable(CalibrationResult result, std::string reason);

// Adds `text` to `result.reason`, after a "; " when it already holds something.
void append_reason(CalibrationResult& result, const std::string& text);

// Every status's name, in declaration order: "ok", "insufficient_data", "unreliable".
std::vector<std::string> calibration_status_names();

}  // namespace x2car
