#include "x2car/core/calibration_result.hpp"

#include <stdexcept>

#include "x2car/core/enum_names.hpp"

namespace x2car {

constexpr std::array<EnumName<CalibrationStatus>, 3> kCalibrationStatusNames{{
    {CalibrationStatus::kOk, "ok"},
    {CalibrationStatus::kInsufficientData, "insufficient_data"},
    {CalibrationStatus::kUnreliable, "unreliable"},
}};

const char* to_string(CalibrationStatus status) {
  return enum_to_string(kCalibrationStatusNames, status);
}

CalibrationStatus calibration_status_from_string(const std::string& text) {
  return enum_from_string(kCalibrationStatusNames, text, "calibration status");
}

std::vector<std::string> calibration_status_names() { return enum_names(kCalibrationStatusNames); }

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

CalibrationResult mark_unreliable(CalibrationResult result, std::string reason) {
  result.status = CalibrationStatus::kUnreliable;
  result.reason = std::move(reason);
  return result;
}

void append_reason(CalibrationResult& result, const std::string& text) {
  result.reason += result.reason.empty() ? text : "; " + text;
}

}  // namespace x2car
