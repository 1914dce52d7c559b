// x2car calibrate radar: a 2-D radar's mounting yaw from its detections and the GNSS/INS log
// (x2car/radar).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <optional>
#include <vector>

#include "apps/x2car/bag_inputs.hpp"
#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/ins_inputs.hpp"
#include "apps/x2car/number_checks.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/io/ins_log.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::cli {
namespace {

struct CalibrateRadarArguments {
  std::string input_path;
  std::string ins_path;
  std::string layout = "auto";
  std::string angle_unit = io::to_string(io::RadarReadOptions{}.angle_unit);
  std::optional<std::string> method;
  std::vector<double> lever_arm_m;  // x y of the radar on the car [m], optional
  std::optional<double> min_speed_mps;
  std::optional<double> nominal_yaw_deg;  // the mounting as designed [deg], optional
  BagArguments bag;
  OutputArguments output;
};

radar::RadarCalibrationOptions calibration_options(const CalibrateRadarArguments& arguments) {
  radar::RadarCalibrationOptions options;
  if (arguments.method) options.method = radar::radar_method_from_string(*arguments.method);
  if (arguments.lever_arm_m.size() == 2) {
    options.lever_arm_in_vehicle =
        Eigen::Vector2d(arguments.lever_arm_m[0], arguments.lever_arm_m[1]);
  }
  if (arguments.min_speed_mps) options.min_speed_mps = *arguments.min_speed_mps;
  if (arguments.nominal_yaw_deg) {
    options.velocity.nominal_yaw = rad_from_deg(*arguments.nominal_yaw_deg);
  }
  return options;
}

// "auto" (the layout detected from the files) and every layout of the name table.
std::vector<std::string> radar_layout_choices() {
  std::vector<std::string> choices = {"auto"};
  for (const std::string& name : io::radar_layout_names()) choices.push_back(name);
  return choices;
}

io::RadarReadOptions read_options(const CalibrateRadarArguments& arguments) {
  io::RadarReadOptions options;
  if (arguments.layout != "auto") options.layout = io::radar_layout_from_string(arguments.layout);
  options.angle_unit = io::angle_unit_from_string(arguments.angle_unit);
  options.topic = arguments.bag.topic_or_none();
  options.allow_truncated = arguments.bag.allow_truncated;
  return options;
}

int run_calibrate_radar(const CalibrateRadarArguments& arguments) {
  // A drive folder's GNSS/INS log is an input too, found before any input is read.
  const std::filesystem::path ins_log_path = ins_log_of(arguments.ins_path);
  check_output_arguments(arguments.output, {{{"--input", arguments.input_path},
                                             {"--ins", arguments.ins_path},
                                             {"--ins", ins_log_path.string()}}});
  check_topic_needs_bag(arguments.input_path, arguments.bag);
  const io::RadarReadOptions radar_options = read_options(arguments);
  const io::RadarLog radar_log = io::read_radar(arguments.input_path, radar_options);
  io::InsReadOptions ins_options;
  ins_options.topic = arguments.bag.ins_topic_or_none();
  const io::InsLog ins_log = io::read_ins_log(ins_log_path, ins_options);
  for (const std::string& notice : radar_log.notices) spdlog::warn("{}", notice);
  for (const std::string& notice : ins_log.notices) spdlog::warn("{}", notice);
  spdlog::info("read {} radar detections ({}) from {} and {} GNSS/INS samples from {}",
               radar_log.detections.size(), io::to_string(radar_log.layout), arguments.input_path,
               ins_log.records.size(), ins_log_path.string());
  // The radar's times on the GNSS/INS log's clock.
  const std::vector<io::RadarDetection> detections =
      radar::detections_on_ins_clock(radar_log, ins_log);
  radar::RadarCalibrationOptions options = calibration_options(arguments);
  const std::optional<MountingPrior> prior = bag_prior(arguments.input_path, radar_log.frame_id);
  // The bag's own lever arm when the user gave none: the turns' omega x r term needs it.
  if (prior && !options.lever_arm_in_vehicle) {
    options.lever_arm_in_vehicle = prior->translation.head<2>();
    spdlog::info("the radar's lever arm from the bag's transforms: {:.3f} {:.3f} m",
                 prior->translation.x(), prior->translation.y());
  }
  CalibrationResult result = radar::calibrate_radar(detections, ins_log.records, options);
  result.prior = prior;
  return finish_calibration(result, arguments.output,
                            report_context("radar", arguments.input_path));
}

}  // namespace

RunCommand setup_calibrate_radar_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateRadarArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "Radar folder: scan files (conti, delphi) or detections.csv (generic); or a bag "
                  "(MCAP, ROS 1 .bag, ROS 2 bag folder) with a radar_msgs/RadarScan or "
                  "RadarTracks topic")
      ->type_name("DIR|BAG")
      ->required();
  command
      .add_option("--ins", arguments->ins_path,
                  "GNSS/INS log: novatel_enu.csv, a generic CSV with a header, a KITTI OXTS "
                  "folder, or a bag with a nav_msgs/Odometry or PoseStamped topic (the radar's "
                  "bag itself, for one), or a drive folder holding one")
      ->type_name("PATH")
      ->required();
  command
      .add_option("--layout", arguments->layout,
                  "Layout of the radar files; auto tells conti, delphi, generic and bag apart from "
                  "the files")
      ->type_name("NAME")
      ->check(CLI::IsMember(radar_layout_choices()))
      ->capture_default_str();
  command
      .add_option("--angle-unit", arguments->angle_unit,
                  "Unit of the generic CSV's azimuth and Delphi's bearing (conti has no angle "
                  "column)")
      ->type_name("UNIT")
      ->check(CLI::IsMember(io::angle_unit_names()))
      ->capture_default_str();
  command
      .add_option("--method", arguments->method,
                  "velocity (Doppler of static targets), position (triangles of tracked static "
                  "objects over straight stretches; detections without track ids are associated "
                  "into tracks) or auto (both; reports the more precise one that passed its "
                  "checks, and why)")
      ->type_name("NAME")
      ->check(CLI::IsMember(radar::radar_method_names()))
      ->default_str(radar::to_string(radar::RadarCalibrationOptions{}.method));
  command
      .add_option("--lever-arm", arguments->lever_arm_m,
                  "The radar's x y on the car [m]; with it turns are used, without they are gated "
                  "out")
      ->expected(2)
      ->type_name("X Y");
  command.add_option("--min-speed", arguments->min_speed_mps, "Slower samples are not used [m/s]")
      ->check(positive_number())
      ->default_str(fmt::format("{:g}", radar::RadarCalibrationOptions{}.min_speed_mps));
  command
      .add_option("--nominal-yaw,--nominal-yaw-deg", arguments->nominal_yaw_deg,
                  fmt::format("The radar's yaw as designed [deg] (0 ahead, 90 left, 180 behind); "
                              "the velocity method then searches within +-{:g} deg of it instead "
                              "of the full circle",
                              deg_from_rad(radar::RadarVelocityMethodOptions{}.search_half_range)))
      ->type_name("DEG")
      ->check(CLI::Range(-360.0, 360.0));
  add_bag_options(command, arguments->bag,
                  "A bag's RadarScan or RadarTracks topic (default: its only one)", true);
  add_output_options(command, arguments->output);
  command.footer(
      "Roll and pitch are not observable by a 2-D radar and are reported as null. The yaw is "
      "relative to the car's direction of motion. With --method auto the result's `method` names "
      "the method reported, its note says why, and `diagnostics`/`support` hold both methods' "
      "yaw, standard error and support (velocity_*, position_*). The velocity method fits the "
      "ego-speed scale with the yaw (printed; speed_scale in the JSON). A fit that fails its "
      "checks (residuals against the nominal noise, static share, speed scale, windows, static "
      "targets moving as fitted) is `unreliable`, exit code 1. See docs/methods.md.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate radar --input drive/radar --ins drive/ins/novatel_enu.csv --out "
      "radar.json\n"
      "  x2car calibrate radar --input run.mcap --topic /radar_front/scan --ins run.mcap --out "
      "radar.json");
  return [arguments] { return run_calibrate_radar(*arguments); };
}

}  // namespace x2car::cli
