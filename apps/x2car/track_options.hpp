// The command-line options of the calibrators built on the track alignment (GNSS/INS, LiDAR;
// core/track_alignment.hpp, core/yaw_choice.hpp): which yaw to report and the gates of the
// stretches of driving it is estimated on. Each option is optional: when it is not given the
// library's default stands (the help shows it), so a default lives in one place.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/track_alignment.hpp"
#include "x2car/core/yaw_choice.hpp"

namespace x2car::cli {

struct TrackArguments {
  std::optional<std::string> yaw_method;
  std::optional<double> min_speed_mps;
  std::optional<double> max_curvature_per_m;
  std::optional<double> min_segment_s;
  std::optional<double> min_duration_s;
  std::optional<std::string> turns;                     // use | exclude
  std::optional<double> max_lateral_acceleration_mps2;  // with turns used
  std::vector<double> lever_arm_m;                      // x y z of the sensor on the car [m]
};

// `samples` names what is gated in the help ("samples", "poses").
void add_track_options(CLI::App& command, TrackArguments& arguments, const std::string& samples);

// Sets the given gates on `alignment` and the given yaw method on `yaw_method`.
void apply_track_arguments(const TrackArguments& arguments, TrackAlignmentOptions& alignment,
                           YawMethod& yaw_method);

}  // namespace x2car::cli
