#include "x2car/core/yaw_choice.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace x2car {

const char* to_string(YawMethod method) {
  switch (method) {
    case YawMethod::kAuto:
      return "auto";
    case YawMethod::kTrackHeading:
      return "track_heading";
    case YawMethod::kVelocityDirection:
      return "velocity_direction";
  }
  return "unknown";
}

YawMethod yaw_method_from_string(const std::string& text) {
  for (const auto method :
       {YawMethod::kAuto, YawMethod::kTrackHeading, YawMethod::kVelocityDirection}) {
    if (text == to_string(method)) return method;
  }
  throw std::invalid_argument("unknown yaw method '" + text +
                              "' (auto, track_heading, velocity_direction)");
}

bool DisagreementTest::operator()(double a, double a_std, double b, double b_std) const {
  const double difference = std::abs(angle_difference(a, b));
  return difference > min_difference && difference > sigmas * std::hypot(a_std, b_std);
}

void DisagreementTest::Check() const {
  if (!(sigmas > 0.0)) throw std::invalid_argument("disagreement: sigmas must be positive");
  if (!(min_difference >= 0.0)) {
    throw std::invalid_argument("disagreement: min_difference must be >= 0");
  }
}

YawChoice choose_yaw(const TrackAlignment& alignment, YawMethod method,
                     const DisagreementTest& disagreement) {
  if (!alignment.yaw || !alignment.velocity_yaw_estimate) {
    throw std::invalid_argument("choose_yaw: the alignment has no yaw estimates");
  }
  YawChoice choice;
  choice.track_heading = &*alignment.yaw;
  choice.velocity_direction = &*alignment.velocity_yaw_estimate;
  const SegmentAverage& track_yaw = *choice.track_heading;
  const SegmentAverage& velocity_yaw = *choice.velocity_direction;
  const bool use_velocity =
      method == YawMethod::kVelocityDirection ||
      (method == YawMethod::kAuto && velocity_yaw.standard_error < track_yaw.standard_error);
  choice.method = use_velocity ? YawMethod::kVelocityDirection : YawMethod::kTrackHeading;
  choice.reported = use_velocity ? &velocity_yaw : &track_yaw;
  choice.difference = angle_difference(velocity_yaw.value, track_yaw.value);
  if (disagreement(velocity_yaw.value, velocity_yaw.standard_error, track_yaw.value,
                   track_yaw.standard_error)) {
    choice.disagreement = fmt::format(
        "the velocity-direction yaw ({:.3f} deg) differs from the track-heading yaw ({:.3f} deg) "
        "by {:.3f} deg, more than {:g} standard errors",
        deg_from_rad(velocity_yaw.value), deg_from_rad(track_yaw.value),
        deg_from_rad(choice.difference), disagreement.sigmas);
  }
  return choice;
}

void write_yaw_choice(const YawChoice& choice, CalibrationResult& result) {
  result.yaw = choice.reported->value;
  result.yaw_std = choice.reported->standard_error;
  result.method = to_string(choice.method);
  result.diagnostics["track_method_yaw_deg"] = deg_from_rad(choice.track_heading->value);
  result.diagnostics["track_method_yaw_std_deg"] =
      deg_from_rad(choice.track_heading->standard_error);
  result.diagnostics["velocity_method_yaw_deg"] = deg_from_rad(choice.velocity_direction->value);
  result.diagnostics["velocity_method_yaw_std_deg"] =
      deg_from_rad(choice.velocity_direction->standard_error);
  result.diagnostics["yaw_disagreement_deg"] = deg_from_rad(choice.difference);
}

}  // namespace x2car
