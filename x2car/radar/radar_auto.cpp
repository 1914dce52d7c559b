#include "x2car/radar/radar_auto.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace x2car::radar {
namespace {

// Adds one method's figures, prefixed with its name, to the reported result.
void add_method_summary(CalibrationResult& reported, const CalibrationResult& method) {
  const std::string prefix = method.method + "_";
  reported.diagnostics[prefix + "ok"] = method.ok() ? 1.0 : 0.0;
  // An unreliable fit's figures too, for inspection (prefix_ok says it is not a mounting).
  if (method.yaw && method.yaw_std) {
    reported.diagnostics[prefix + "yaw_deg"] = deg_from_rad(*method.yaw);
    reported.diagnostics[prefix + "std_deg"] = deg_from_rad(*method.yaw_std);
  }
  for (const auto& [name, value] : method.diagnostics) {
    reported.diagnostics[prefix + name] = value;
  }
  for (const auto& [name, value] : method.support) reported.support[prefix + name] = value;
}

std::int64_t support_of(const CalibrationResult& result, const std::string& name) {
  const auto found = result.support.find(name);
  return found == result.support.end() ? 0 : found->second;
}

}  // namespace

CalibrationResult choose_radar_method(CalibrationResult velocity, CalibrationResult position,
                                      const RadarAutoOptions& options) {
  if (!velocity.ok() && !position.ok()) {
    const std::string reason =
        fmt::format("velocity method: {}; position method: {}", velocity.reason, position.reason);
    const bool any_unreliable = velocity.status == CalibrationStatus::kUnreliable ||
                                position.status == CalibrationStatus::kUnreliable;
    // A fit that failed its checks keeps its figures for inspection; nothing is ok.
    CalibrationResult result =
        any_unreliable
            ? mark_unreliable(
                  velocity.status == CalibrationStatus::kUnreliable ? velocity : position, reason)
            : insufficient_data("radar", reason);
    result.method = "auto";
    add_method_summary(result, velocity);
    add_method_summary(result, position);
    return result;
  }
  if (!velocity.ok() || !position.ok()) {
    CalibrationResult& chosen = velocity.ok() ? velocity : position;
    const CalibrationResult& other = velocity.ok() ? position : velocity;
    chosen.reason = fmt::format("auto: only the {} method found a yaw ({} method, {}: {})",
                                chosen.method, other.method, to_string(other.status), other.reason);
    CalibrationResult result = chosen;
    add_method_summary(result, velocity);
    add_method_summary(result, position);
    return result;
  }
  const double difference = angle_difference(*velocity.yaw, *position.yaw);
  const double tolerance =
      options.agreement_sigmas * std::hypot(*velocity.yaw_std, *position.yaw_std) +
      options.agreement_floor;
  const std::int64_t static_objects = support_of(position, "static_objects");
  std::string reason;
  bool take_position = false;
  if (std::abs(difference) <= tolerance) {
    take_position = *position.yaw_std < *velocity.yaw_std;
    reason = fmt::format(
        "auto: the velocity and position methods agree ({:.3f} vs {:.3f} deg, within {:.3f}); "
        "reported the {} method, whose standard error is smaller ({:.3f} vs {:.3f} deg)",
        deg_from_rad(*velocity.yaw), deg_from_rad(*position.yaw), deg_from_rad(tolerance),
        take_position ? "position" : "velocity",
        deg_from_rad(take_position ? *position.yaw_std : *velocity.yaw_std),
        deg_from_rad(take_position ? *velocity.yaw_std : *position.yaw_std));
  } else {
    // Both passed their own checks, and the velocity method fits the speed scale itself, so the
    // Doppler is not presumed the culprit: the more precise method is reported, provided enough
    // static objects stand behind the position method's standard error.
    const bool enough_objects = static_objects >= options.min_position_objects;
    take_position = enough_objects && *position.yaw_std < *velocity.yaw_std;
    reason = fmt::format(
        "auto: the methods disagree (velocity {:.3f}, position {:.3f} deg, {:.3f} apart, more than "
        "{:.3f}); reported the {} method: {}",
        deg_from_rad(*velocity.yaw), deg_from_rad(*position.yaw),
        deg_from_rad(std::abs(difference)), deg_from_rad(tolerance),
        take_position ? "position" : "velocity",
        !enough_objects
            ? fmt::format("only {} static objects support the position method (need {})",
                          static_objects, options.min_position_objects)
            : fmt::format("its standard error is smaller ({:.3f} vs {:.3f} deg)",
                          deg_from_rad(take_position ? *position.yaw_std : *velocity.yaw_std),
                          deg_from_rad(take_position ? *velocity.yaw_std : *position.yaw_std)));
  }
  CalibrationResult result = take_position ? position : velocity;
  result.reason = reason;
  if (std::abs(difference) > options.max_disagreement) {
    result = mark_unreliable(
        std::move(result),
        fmt::format("auto: the velocity and position methods disagree by {:.3f} deg (velocity "
                    "{:.3f}, position {:.3f} deg), more than {:g} deg: at least one is wrong and "
                    "the data do not say which",
                    deg_from_rad(std::abs(difference)), deg_from_rad(*velocity.yaw),
                    deg_from_rad(*position.yaw), deg_from_rad(options.max_disagreement)));
  }
  add_method_summary(result, velocity);
  add_method_summary(result, position);
  result.diagnostics["methods_difference_deg"] = deg_from_rad(difference);
  result.diagnostics["methods_tolerance_deg"] = deg_from_rad(tolerance);
  for (const Series& series : (take_position ? velocity : position).series) {
    result.series.push_back(series);
  }
  return result;
}

}  // namespace x2car::radar
