#include "x2car/core/yaw_choice.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car {

constexpr std::array<EnumName<YawMethod>, 3> kYawMethodNames{{
    {YawMethod::kAuto, "auto"},
    {YawMethod::kTrackHeading, "track_heading"},
    {YawMethod::kVelocityDirection, "velocity_direction"},
}};

const char* to_string(YawMethod method) { return enum_to_string(kYawMethodNames, method); }

YawMethod yaw_method_from_string(const std::string& text) {
  return enum_from_string(kYawMethodNames, text, "yaw method");
}

std::vector<std::string> yaw_method_names() { return enum_names(kYawMethodNames); }

bool DisagreementTest::operator()(double a, double a_std, double b, double b_std) const {
  const double difference = std::abs(angle_difference(a, b));
  return difference > min_difference && difference > sigmas * std::hypot(a_std, b_std);
}

void DisagreementTest::Check() const {
  const OptionsCheck check("DisagreementTest");
  check.positive("sigmas", sigmas);
  check.non_negative("min_difference", min_difference);
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
