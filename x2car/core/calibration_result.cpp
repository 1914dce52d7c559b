#include "x2car/core/calibration_result.hpp"

#include <stdexcept>

namespace x2car {

const char* to_string(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::kOk:
      return "ok";
    case CalibrationStatus::kInsufficientData:
      return "insufficient_data";
  }
  return "unknown";
}

CalibrationStatus calibration_status_from_string(const std::string& text) {
  if (text == "ok") return CalibrationStatus::kOk;
  if (text == "insufficient_data") return CalibrationStatus::kInsufficientData;
  throw std::invalid_argument("unknown calibration status '" + text + "'");
}

EulerAngles CalibrationResult::angles_or_zero() const {
  return {roll.value_or(0.0), pitch.value_or(0.0), yaw.value_or(0.0)};
}

CalibrationResult insufficient_data(std::string sensor, std::string reason) {
  CalibrationResult result;
  result.sensor = std::move(sensor);
  result.status = CalibrationStatus::kInsufficientData;
  result.reason = std::move(reason);
  return result;
}

}  // namespace x2car
