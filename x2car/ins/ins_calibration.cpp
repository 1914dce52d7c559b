#include "x2car/ins/ins_calibration.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "x2car/core/options_check.hpp"
#include "x2car/core/track_alignment_report.hpp"

namespace x2car::ins {
namespace {

constexpr const char* kSensor = "ins";

bool reports_velocity(std::span<const io::InsRecord> records) {
  for (const io::InsRecord& record : records) {
    if (record.velocity_enu.squaredNorm() > 0.0) return true;
  }
  return false;
}

SensorTrack sensor_track_from(std::span<const io::InsRecord> records, bool with_velocity) {
  SensorTrack track;
  track.time.reserve(records.size());
  track.position_enu.reserve(records.size());
  track.world_from_sensor.reserve(records.size());
  for (const io::InsRecord& record : records) {
    track.time.push_back(record.time);
    track.position_enu.push_back(record.position_enu);
    track.world_from_sensor.push_back(rotation_from_euler(record.attitude));
    if (with_velocity) track.velocity_enu.push_back(record.velocity_enu);
  }
  return track;
}

// The reason that goes with a yaw the two methods disagree on.
std::optional<std::string> disagreement_reason(const YawChoice& choice) {
  if (!choice.disagreement) return std::nullopt;
  return *choice.disagreement +
         ": check for sideslip, a lever arm far from the rear axle, or velocities in another frame";
}

// The device's attitude bias, constant over the drive, is in the angles whatever the data's
// spread: added in quadrature to their standard errors, the two yaw methods' included. The yaw
// choice and the disagreement test compare the data's own errors (both methods share the bias).
void add_device_bias(const DeviceAttitudeBias& bias, CalibrationResult& result) {
  result.yaw_std = std::hypot(*result.yaw_std, bias.heading);
  result.pitch_std = std::hypot(*result.pitch_std, bias.pitch);
  for (const char* key : {"track_method_yaw_std_deg", "velocity_method_yaw_std_deg"}) {
    double& standard_error_deg = result.diagnostics.at(key);
    standard_error_deg = std::hypot(standard_error_deg, deg_from_rad(bias.heading));
  }
}

}  // namespace

void DeviceAttitudeBias::Check() const {
  const OptionsCheck check("DeviceAttitudeBias");
  check.non_negative("heading", heading);
  check.non_negative("pitch", pitch);
}

void InsCalibrationOptions::Check() const {
  alignment.Check();
  disagreement.Check();
  device_bias.Check();
}

CalibrationResult calibrate_ins(std::span<const io::InsRecord> records,
                                const InsCalibrationOptions& options) {
  options.Check();
  const auto started = std::chrono::steady_clock::now();
  // The spline needs a handful of samples; far fewer than any usable drive.
  constexpr std::size_t kMinRecords = 16;
  if (records.size() < kMinRecords) {
    return insufficient_data(
        kSensor, fmt::format("only {} GNSS/INS samples; need at least {} and "
                             "{:g} s of straight driving",
                             records.size(), kMinRecords, options.alignment.min_valid_duration_s));
  }
  const bool with_velocity = options.use_device_velocity && reports_velocity(records);
  const TrackAlignment alignment =
      align_track(sensor_track_from(records, with_velocity), options.alignment);
  std::optional<YawChoice> choice;
  if (!alignment.insufficient_reason) {
    choice = choose_yaw(alignment, options.yaw_method, options.disagreement);
  }

  CalibrationResult result;
  result.sensor = kSensor;
  write_track_alignment(alignment, choice, options.keep_series, result);
  result.diagnostics["velocity_from_device"] = alignment.velocity_from_sensor ? 1.0 : 0.0;
  if (!choice) {
    result.status = CalibrationStatus::kInsufficientData;
    result.reason = *alignment.insufficient_reason;
  } else {
    result.status = CalibrationStatus::kOk;
    result.pitch = alignment.velocity_pitch_estimate->value;
    result.pitch_std = alignment.velocity_pitch_estimate->standard_error;
    result.diagnostics["pitch_per_acceleration_deg_per_mps2"] =
        deg_from_rad(alignment.pitch_per_acceleration);
    result.reason = disagreement_reason(*choice).value_or("");
    add_device_bias(options.device_bias, result);
  }
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace x2car::ins
