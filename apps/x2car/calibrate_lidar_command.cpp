// x2car calibrate lidar: the LiDAR's roll, pitch, yaw and height from a folder of sweeps
// (x2car/lidar).
#include <spdlog/spdlog.h>

#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/sweep_folder.hpp"

namespace x2car::cli {
namespace {

struct CalibrateLidarArguments {
  std::string input_path;
  std::string yaw_method = "auto";
  int ground_every = 2;
  double max_turn_rate_deg_s = 2.865;  // 0.05 rad/s
  double min_speed = 3.0;
  double max_curvature = 0.01;
  double min_segment_s = 5.0;
  OutputArguments output;
};

lidar::LidarCalibrationOptions calibration_options(const CalibrateLidarArguments& arguments) {
  lidar::LidarCalibrationOptions options;
  options.yaw_method = yaw_method_from_string(arguments.yaw_method);
  options.ground_every = arguments.ground_every;
  options.max_ground_turn_rate = rad_from_deg(arguments.max_turn_rate_deg_s);
  options.alignment.segments.min_speed = arguments.min_speed;
  options.alignment.segments.max_abs_curvature = arguments.max_curvature;
  options.alignment.segments.min_duration_s = arguments.min_segment_s;
  options.keep_series = !arguments.output.without_series;
  return options;
}

int run_calibrate_lidar(const CalibrateLidarArguments& arguments) {
  const lidar::SweepFolder folder = lidar::list_sweeps(arguments.input_path);
  spdlog::info("found {} sweeps in {} (times from {}; {} other files ignored)",
               folder.sweeps.size(), folder.folder.string(), folder.time_source,
               folder.ignored_files);
  const CalibrationResult result =
      lidar::calibrate_lidar(lidar::sweep_source_from(folder), calibration_options(arguments));
  return finish_calibration(result, arguments.output);
}

}  // namespace

RunCommand setup_calibrate_lidar_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateLidarArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "Folder of sweeps: PCD files named by time (or with times.txt), KITTI "
                  "velodyne/*.bin with times.txt, or a drive folder holding lidar/")
      ->type_name("DIR")
      ->required();
  command
      .add_option("--yaw-method", arguments->yaw_method,
                  "Yaw reported: auto (smaller standard error), track_heading (the paper's) or "
                  "velocity_direction")
      ->type_name("NAME")
      ->check(CLI::IsMember({"auto", "track_heading", "velocity_direction"}))
      ->capture_default_str();
  command
      .add_option("--ground-every", arguments->ground_every,
                  "Fit the ground plane on every k-th sweep")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      .add_option("--max-turn-rate", arguments->max_turn_rate_deg_s,
                  "Sweeps turning faster are not used for the ground [deg/s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      .add_option("--min-speed", arguments->min_speed, "Slower poses are not used for yaw [m/s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command
      .add_option("--max-curvature", arguments->max_curvature,
                  "Poses in sharper turns are not used for yaw [1/m]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      .add_option("--min-segment", arguments->min_segment_s,
                  "Shortest run of usable poses kept for yaw [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  add_output_options(command, arguments->output);
  command.footer(
      "Roll, pitch and the height (z) come from the ground plane, yaw from the odometry's track. "
      "See docs/methods.md.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate lidar --input drive/lidar --out lidar.json");
  return [arguments] { return run_calibrate_lidar(*arguments); };
}

}  // namespace x2car::cli
