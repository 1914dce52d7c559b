#include "apps/x2car/track_options.hpp"

#include <fmt/format.h>

#include "apps/x2car/number_checks.hpp"

namespace x2car::cli {

void add_track_options(CLI::App& command, TrackArguments& arguments, const std::string& samples) {
  const TrackAlignmentOptions defaults;
  command
      .add_option("--yaw-method", arguments.yaw_method,
                  "Yaw reported: auto (smaller standard error), track_heading (the paper's) or "
                  "velocity_direction")
      ->type_name("NAME")
      ->check(CLI::IsMember({"auto", "track_heading", "velocity_direction"}))
      ->default_str(to_string(YawMethod::kAuto));
  command
      .add_option("--min-speed", arguments.min_speed_mps,
                  "Slower " + samples + " are not used [m/s]")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.segments.min_speed));
  command
      .add_option("--max-curvature", arguments.max_curvature_per_m,
                  "The " + samples + " of sharper turns are not used [1/m]")
      ->check(positive_number())
      ->default_str(fmt::format("{:g}", defaults.segments.max_abs_curvature));
  command
      .add_option("--min-segment", arguments.min_segment_s,
                  "Shortest run of usable " + samples + " kept [s]")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.segments.min_duration_s));
  command
      .add_option("--min-duration", arguments.min_duration_s,
                  "Usable driving needed for a yaw [s]; lower it knowingly: the standard error "
                  "grows as the driving shrinks")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.min_valid_duration_s));
}

void apply_track_arguments(const TrackArguments& arguments, TrackAlignmentOptions& alignment,
                           YawMethod& yaw_method) {
  if (arguments.yaw_method) yaw_method = yaw_method_from_string(*arguments.yaw_method);
  if (arguments.min_speed_mps) alignment.segments.min_speed = *arguments.min_speed_mps;
  if (arguments.max_curvature_per_m) {
    alignment.segments.max_abs_curvature = *arguments.max_curvature_per_m;
  }
  if (arguments.min_segment_s) alignment.segments.min_duration_s = *arguments.min_segment_s;
  if (arguments.min_duration_s) alignment.min_valid_duration_s = *arguments.min_duration_s;
}

}  // namespace x2car::cli
