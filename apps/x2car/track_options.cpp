#include "apps/x2car/track_options.hpp"

namespace x2car::cli {

void add_track_options(CLI::App& command, TrackArguments& arguments, const std::string& samples) {
  command
      .add_option("--yaw-method", arguments.yaw_method,
                  "Yaw reported: auto (smaller standard error), track_heading (the paper's) or "
                  "velocity_direction")
      ->type_name("NAME")
      ->check(CLI::IsMember({"auto", "track_heading", "velocity_direction"}))
      ->capture_default_str();
  command
      .add_option("--min-speed", arguments.min_speed, "Slower " + samples + " are not used [m/s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command
      .add_option("--max-curvature", arguments.max_curvature,
                  "The " + samples + " of sharper turns are not used [1/m]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      .add_option("--min-segment", arguments.min_segment_s,
                  "Shortest run of usable " + samples + " kept [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

YawMethod apply_track_arguments(const TrackArguments& arguments, TrackAlignmentOptions& alignment) {
  alignment.segments.min_speed = arguments.min_speed;
  alignment.segments.max_abs_curvature = arguments.max_curvature;
  alignment.segments.min_duration_s = arguments.min_segment_s;
  return yaw_method_from_string(arguments.yaw_method);
}

}  // namespace x2car::cli
