// x2car calibrate ins: the GNSS/INS mounting yaw and pitch from a drive (x2car/ins).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/x2car/bag_inputs.hpp"
#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/ins_inputs.hpp"
#include "apps/x2car/subcommand.hpp"
#include "apps/x2car/track_options.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/ins/ins_calibration.hpp"
#include "x2car/io/ins_log.hpp"

namespace x2car::cli {
namespace {

struct CalibrateInsArguments {
  std::string input_path;
  std::string format = "auto";
  std::string yaw_convention;  // empty: as the CSV header says
  std::string angle_unit = io::to_string(io::InsCsvOptions{}.angle_unit);
  std::vector<std::string> columns;  // --columns time=GPS Time,east=E,...
  std::string topic;                 // a bag's pose or NavSatFix topic
  std::string imu_topic;             // the Imu topic beside a NavSatFix topic
  TrackArguments track;
  bool spline_velocity = false;
  OutputArguments output;
};

io::InsReadOptions read_options(const CalibrateInsArguments& arguments) {
  io::InsReadOptions options;
  options.format = io::ins_format_from_string(arguments.format);
  if (!arguments.yaw_convention.empty()) {
    options.csv.yaw_convention = io::yaw_convention_from_string(arguments.yaw_convention);
  }
  options.csv.angle_unit = io::angle_unit_from_string(arguments.angle_unit);
  for (const std::string& pair : arguments.columns) {
    const std::size_t equals = pair.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == pair.size()) {
      throw std::invalid_argument(
          fmt::format("--columns: '{}' is not NAME=COLUMN (e.g. time=GPS Time,east=E)", pair));
    }
    options.csv.column_names[pair.substr(0, equals)] = pair.substr(equals + 1);
  }
  options.csv.Check();
  if (!arguments.topic.empty()) options.topic = arguments.topic;
  if (!arguments.imu_topic.empty()) options.imu_topic = arguments.imu_topic;
  return options;
}

ins::InsCalibrationOptions calibration_options(const CalibrateInsArguments& arguments) {
  ins::InsCalibrationOptions options;
  apply_track_arguments(arguments.track, options.alignment, options.yaw_method);
  options.use_device_velocity = !arguments.spline_velocity;
  options.keep_series = !arguments.output.without_series;
  return options;
}

int run_calibrate_ins(const CalibrateInsArguments& arguments) {
  // A drive folder's log is an input too.
  const std::filesystem::path log_path = ins_log_of(arguments.input_path);
  check_output_arguments(arguments.output,
                         {{{"--input", arguments.input_path}, {"--input", log_path.string()}}});
  const io::InsLog log = io::read_ins_log(log_path, read_options(arguments));
  for (const std::string& notice : log.notices) spdlog::warn("{}", notice);
  spdlog::info("read {} GNSS/INS samples ({}) from {}", log.records.size(),
               io::to_string(log.format), arguments.input_path);
  CalibrationResult result = ins::calibrate_ins(log.records, calibration_options(arguments));
  result.prior = bag_prior(arguments.input_path, log.frame_id);
  return finish_calibration(result, arguments.output, report_context("ins", arguments.input_path));
}

}  // namespace

RunCommand setup_calibrate_ins_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateInsArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "GNSS/INS log: novatel_enu.csv, a generic CSV with a header, a KITTI OXTS "
                  "folder, a bag (MCAP, ROS 1 .bag, ROS 2 bag folder) with a nav_msgs/Odometry or "
                  "geometry_msgs/PoseStamped topic, or sensor_msgs/NavSatFix with "
                  "sensor_msgs/Imu, or a drive folder holding one "
                  "(ins/novatel_enu.csv or x2car.yaml)")
      ->type_name("PATH")
      ->required();
  command.add_option("--format", arguments->format, "Form of the input; auto detects it")
      ->type_name("FORM")
      ->check(CLI::IsMember(io::ins_format_names()))
      ->capture_default_str();
  command
      .add_option("--yaw-convention", arguments->yaw_convention,
                  "For a generic CSV: read its yaw/heading column as enu (counter-clockwise from "
                  "east) or azimuth (clockwise from north)")
      ->type_name("NAME")
      ->check(CLI::IsMember(io::yaw_convention_names()));
  command
      .add_option("--angle-unit", arguments->angle_unit,
                  "For a generic CSV: unit of the roll, pitch and yaw/heading columns whose names "
                  "have no _deg or _rad suffix")
      ->type_name("UNIT")
      ->check(CLI::IsMember(io::angle_unit_names()))
      ->capture_default_str();
  command
      .add_option("--columns", arguments->columns,
                  "A generic CSV's header names read as x2car's, NAME=COLUMN separated by commas, "
                  "e.g. time_ms=Timestamp,east=E,north=N,up=U,heading_deg=Hdg (docs/formats.md)")
      ->type_name("LIST")
      ->delimiter(',');
  command
      .add_option("--topic", arguments->topic,
                  "A bag's Odometry, PoseStamped or NavSatFix topic (default: its only pose "
                  "topic, else its only NavSatFix topic)")
      ->type_name("TOPIC");
  command
      .add_option("--imu-topic", arguments->imu_topic,
                  "With a NavSatFix topic: the Imu topic whose orientation gives the attitude "
                  "(default: its only one)")
      ->type_name("TOPIC");
  add_track_options(command, arguments->track, "samples");
  command.add_flag("--spline-velocity", arguments->spline_velocity,
                   "Ignore the device's velocity; use the smoothed track's");
  add_output_options(command, arguments->output);
  command.footer(
      "Roll is not observable from driving and is reported as null. See docs/methods.md.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate ins --input drive/ins/novatel_enu.csv --out ins.json");
  return [arguments] { return run_calibrate_ins(*arguments); };
}

}  // namespace x2car::cli
