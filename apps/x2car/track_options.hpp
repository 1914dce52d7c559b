// The command-line options of the calibrators built on the track alignment (GNSS/INS, LiDAR;
// core/track_alignment.hpp, core/yaw_choice.hpp): which yaw to report and the gates of the
// stretches of driving it is estimated on.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "x2car/core/track_alignment.hpp"
#include "x2car/core/yaw_choice.hpp"

namespace x2car::cli {

struct TrackArguments {
  std::string yaw_method = "auto";
  double min_speed = 3.0;       // [m/s]
  double max_curvature = 0.01;  // [1/m]
  double min_segment_s = 5.0;   // [s]
};

// `samples` names what is gated in the help ("samples", "poses").
void add_track_options(CLI::App& command, TrackArguments& arguments, const std::string& samples);

// Sets the alignment's gates and returns the yaw method.
YawMethod apply_track_arguments(const TrackArguments& arguments, TrackAlignmentOptions& alignment);

}  // namespace x2car::cli
