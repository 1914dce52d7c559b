// x2car calibrate lidar: the LiDAR's roll, pitch, yaw and height from a folder of sweeps or a
// bag's PointCloud2 topic (x2car/lidar).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <optional>

#include "apps/x2car/bag_inputs.hpp"
#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/number_checks.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/subcommand.hpp"
#include "apps/x2car/track_options.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/lidar/bag_sweeps.hpp"
#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/sweep_folder.hpp"

namespace x2car::cli {
namespace {

struct CalibrateLidarArguments {
  std::string input_path;
  std::optional<int> ground_every;
  std::optional<double> max_turn_rate_deg_s;
  bool skip_bad_sweeps = false;
  BagArguments bag;
  TrackArguments track;
  OutputArguments output;
};

lidar::LidarCalibrationOptions calibration_options(const CalibrateLidarArguments& arguments) {
  lidar::LidarCalibrationOptions options;
  apply_track_arguments(arguments.track, options.alignment, options.yaw_method);
  if (arguments.ground_every) options.ground_every = *arguments.ground_every;
  if (arguments.max_turn_rate_deg_s) {
    options.max_ground_turn_rate = rad_from_deg(*arguments.max_turn_rate_deg_s);
  }
  options.keep_series = !arguments.output.without_series;
  options.skip_bad_sweeps = arguments.skip_bad_sweeps;
  return options;
}

int run_calibrate_lidar(const CalibrateLidarArguments& arguments) {
  check_output_arguments(arguments.output, {{{"--input", arguments.input_path}}});
  lidar::SweepSource sweeps;
  std::string frame_id;  // a bag's sensor frame, for its tf prior
  check_topic_needs_bag(arguments.input_path, arguments.bag);
  if (io::bag_container_of(arguments.input_path)) {
    lidar::BagSweeps bag = lidar::sweeps_from_bag(
        arguments.input_path,
        {.topic = arguments.bag.topic_or_none(), .allow_truncated = arguments.bag.allow_truncated});
    spdlog::info("found {} sweeps on {} (frame '{}') in {}", bag.source.times.size(), bag.topic,
                 bag.frame_id, arguments.input_path);
    sweeps = std::move(bag.source);
    frame_id = bag.frame_id;
  } else {
    const lidar::SweepFolder folder = lidar::list_sweeps(arguments.input_path);
    spdlog::info("found {} sweeps in {} (times from {}; {} other files ignored)",
                 folder.sweeps.size(), folder.folder.string(), folder.time_source,
                 folder.ignored_files);
    sweeps = lidar::sweep_source_from(folder);
  }
  lidar::LidarCalibrationOptions options = calibration_options(arguments);
  ProgressBar progress("sweeps", spdlog::should_log(spdlog::level::info));
  options.progress = progress.callback();
  CalibrationResult result = lidar::calibrate_lidar(sweeps, options);
  progress.finish();
  result.prior = bag_prior(arguments.input_path, frame_id);
  return finish_calibration(result, arguments.output,
                            report_context("lidar", arguments.input_path));
}

}  // namespace

RunCommand setup_calibrate_lidar_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateLidarArguments>();
  const lidar::LidarCalibrationOptions defaults;
  command
      .add_option("-i,--input", arguments->input_path,
                  "Folder of sweeps: PCD files named by time (or with times.txt), KITTI "
                  "velodyne/*.bin with times.txt, or a drive folder holding lidar/; or a bag "
                  "(MCAP, ROS 1 .bag, ROS 2 bag folder) with a sensor_msgs/PointCloud2 topic")
      ->type_name("DIR|BAG")
      ->required();
  command
      .add_option("--ground-every", arguments->ground_every,
                  "Fit the ground plane on every k-th sweep")
      ->check(positive_number())
      ->default_str(std::to_string(defaults.ground_every));
  command
      .add_option("--max-turn-rate-deg", arguments->max_turn_rate_deg_s,
                  "Sweeps turning faster are not used for the ground [deg/s]")
      ->check(positive_number())
      ->default_str(fmt::format("{:.4g}", deg_from_rad(defaults.max_ground_turn_rate)));
  command.add_flag("--skip-bad-sweeps", arguments->skip_bad_sweeps,
                   "Skip sweeps that cannot be read (truncated, corrupt) instead of stopping; "
                   "they are counted in the result");
  add_bag_options(command, arguments->bag, "A bag's PointCloud2 topic (default: its only one)",
                  false);
  add_track_options(command, arguments->track, "poses");
  add_output_options(command, arguments->output);
  command.footer(
      "Roll, pitch and the height (z) come from the ground plane, yaw from the odometry's track. "
      "See docs/methods.md.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate lidar --input drive/lidar --out lidar.json\n"
      "  x2car calibrate lidar --input run.bag --topic /velodyne_points --out lidar.json");
  return [arguments] { return run_calibrate_lidar(*arguments); };
}

}  // namespace x2car::cli
