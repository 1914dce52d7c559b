// x2car calibrate ins: the GNSS/INS mounting yaw and pitch from a drive (x2car/ins).
#include <spdlog/spdlog.h>

#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/ins/ins_calibration.hpp"
#include "x2car/io/ins_log.hpp"

namespace x2car::cli {
namespace {

struct CalibrateInsArguments {
  std::string input_path;
  std::string format = "auto";
  std::string yaw_convention;  // empty: as the CSV header says
  std::string yaw_method = "auto";
  double min_speed = 3.0;
  double max_curvature = 0.01;
  double min_segment_s = 5.0;
  bool spline_velocity = false;
  OutputArguments output;
};

io::InsReadOptions read_options(const CalibrateInsArguments& arguments) {
  io::InsReadOptions options;
  options.format = io::ins_format_from_string(arguments.format);
  if (!arguments.yaw_convention.empty()) {
    options.csv.yaw_convention = io::yaw_convention_from_string(arguments.yaw_convention);
  }
  return options;
}

ins::InsCalibrationOptions calibration_options(const CalibrateInsArguments& arguments) {
  ins::InsCalibrationOptions options;
  options.yaw_method = yaw_method_from_string(arguments.yaw_method);
  options.alignment.segments.min_speed = arguments.min_speed;
  options.alignment.segments.max_abs_curvature = arguments.max_curvature;
  options.alignment.segments.min_duration_s = arguments.min_segment_s;
  options.use_device_velocity = !arguments.spline_velocity;
  options.keep_series = !arguments.output.without_series;
  return options;
}

int run_calibrate_ins(const CalibrateInsArguments& arguments) {
  const io::InsLog log = io::read_ins_log(arguments.input_path, read_options(arguments));
  spdlog::info("read {} GNSS/INS samples ({}) from {}", log.records.size(),
               io::to_string(log.format), arguments.input_path);
  const CalibrationResult result = ins::calibrate_ins(log.records, calibration_options(arguments));
  return finish_calibration(result, arguments.output);
}

}  // namespace

RunCommand setup_calibrate_ins_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateInsArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "GNSS/INS log: novatel_enu.csv, a generic CSV with a header, or a KITTI OXTS "
                  "folder")
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
      ->check(CLI::IsMember({"enu", "azimuth"}));
  command
      .add_option("--yaw-method", arguments->yaw_method,
                  "Yaw reported: auto (smaller standard error), track_heading (the paper's) or "
                  "velocity_direction")
      ->type_name("NAME")
      ->check(CLI::IsMember({"auto", "track_heading", "velocity_direction"}))
      ->capture_default_str();
  command.add_option("--min-speed", arguments->min_speed, "Slower samples are not used [m/s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command
      .add_option("--max-curvature", arguments->max_curvature,
                  "Samples in sharper turns are not used [1/m]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      .add_option("--min-segment", arguments->min_segment_s,
                  "Shortest run of usable samples kept [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
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
