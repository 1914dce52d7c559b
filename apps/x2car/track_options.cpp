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
      ->check(CLI::IsMember(yaw_method_names()))
      ->default_str(to_string(YawMethod::kAuto));
  command
      .add_option("--min-speed", arguments.min_speed_mps,
                  "Slower " + samples + " are not used [m/s]")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.segments.min_speed));
  command
      .add_option("--max-curvature", arguments.max_curvature_per_m,
                  "With --turns exclude: the " + samples + " of sharper turns are not used [1/m]")
      ->check(positive_number())
      ->default_str(fmt::format("{:g}", defaults.segments.max_abs_curvature));
  command
      .add_option("--min-segment", arguments.min_segment_s,
                  "With --turns exclude: shortest run of usable " + samples + " kept [s]")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.segments.min_duration_s));
  command
      .add_option("--min-duration", arguments.min_duration_s,
                  "Usable driving needed for a yaw [s]; lower it knowingly: the standard error "
                  "grows as the driving shrinks")
      ->check(non_negative_number())
      ->default_str(fmt::format("{:g}", defaults.min_valid_duration_s));
  command
      .add_option("--turns", arguments.turns,
                  "use: keep the " + samples +
                      " in turns of low lateral acceleration, corrected for the sensor's lever "
                      "arm (given, or fitted); exclude: the paper's straight-only gates")
      ->type_name("NAME")
      ->check(CLI::IsMember(turn_samples_names()))
      ->default_str(to_string(defaults.turns.samples));
  command
      .add_option("--max-lateral-acceleration", arguments.max_lateral_acceleration_mps2,
                  "With --turns use: the " + samples +
                      " of harder turns are not used (tyres slip sideways) [m/s^2]")
      ->check(positive_number())
      ->default_str(fmt::format("{:g}", defaults.turns.max_lateral_acceleration));
  command
      .add_option("--lever-arm", arguments.lever_arm_m,
                  "The sensor's x y z on the car from the rear axle [m] (x forward); without it "
                  "x is fitted from the turns")
      ->expected(3)
      ->type_name("X Y Z");
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
  if (arguments.turns) alignment.turns.samples = turn_samples_from_string(*arguments.turns);
  if (arguments.max_lateral_acceleration_mps2) {
    alignment.turns.max_lateral_acceleration = *arguments.max_lateral_acceleration_mps2;
  }
  if (arguments.lever_arm_m.size() == 3) {
    alignment.turns.lever_arm = Eigen::Vector3d(arguments.lever_arm_m[0], arguments.lever_arm_m[1],
                                                arguments.lever_arm_m[2]);
  }
}

}  // namespace x2car::cli
