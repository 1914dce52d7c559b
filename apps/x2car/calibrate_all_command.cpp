// x2car calibrate all: every sensor of a simulate-style drive folder (io/drive_folder.hpp), each
// by its own `calibrate SENSOR` command with that command's defaults, so that a sensor's result is
// byte for byte the one its own command gives (the sensors run side by side); then one JSON keyed
// by sensor, one Autoware YAML and one URDF with every sensor that calibrated, a table against the
// ground truth when the folder has one, and on request the report.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/task_group.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/command_output.hpp"
#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/report_output.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/extrinsic.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/drive_folder.hpp"
#include "x2car/io/extrinsic_formats.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/urdf_joint.hpp"

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;

struct CalibrateAllArguments {
  std::string input_path;
  OutputArguments output;
};

// A folder for the sensors' own result files, removed when the run ends (however it ends).
class ScratchFolder {
 public:
  ScratchFolder()
      : path_(fs::temp_directory_path() / fmt::format("x2car-calibrate-all-{}", ::getpid())) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The sensor's own command line, as a user would type it after `x2car calibrate <kind>`.
std::vector<std::string> sensor_arguments(const io::DriveSensor& sensor,
                                          const io::DriveFolder& drive,
                                          const CalibrateAllArguments& arguments,
                                          const fs::path& json) {
  std::vector<std::string> line = {"--input", sensor.input.string()};
  if (sensor.topic) line.insert(line.end(), {"--topic", *sensor.topic});
  if (sensor.kind == io::SensorKind::kRadar || sensor.kind == io::SensorKind::kCamera) {
    if (drive.ins_log) {
      line.insert(line.end(), {"--ins", drive.ins_log->string()});
      if (drive.ins_topic) line.insert(line.end(), {"--ins-topic", *drive.ins_topic});
    } else if (sensor.kind == io::SensorKind::kRadar) {
      throw InputError(sensor.input.string(),
                       "a radar needs the car's motion: the drive has no GNSS/INS log (no "
                       "ins/novatel_enu.csv, nor a sensor of type ins in x2car.yaml)");
    }
  }
  // What a manifest (x2car.yaml) says of the sensor, as the command's own options.
  if (sensor.intrinsics) line.insert(line.end(), {"--intrinsics", sensor.intrinsics->string()});
  if (sensor.lever_arm_m) {
    line.insert(line.end(), {"--lever-arm", fmt::format("{}", (*sensor.lever_arm_m)[0]),
                             fmt::format("{}", (*sensor.lever_arm_m)[1])});
  }
  if (sensor.nominal_yaw_deg) {
    line.insert(line.end(), {"--nominal-yaw", fmt::format("{}", *sensor.nominal_yaw_deg)});
  }
  line.insert(line.end(), {"--out", json.string()});
  if (arguments.output.without_series) line.emplace_back("--without-series");
  if (arguments.output.reproducible) line.emplace_back("--reproducible");
  return line;
}

using SetupCommand = RunCommand (*)(CLI::App&);

SetupCommand setup_for(io::SensorKind kind) {
  switch (kind) {
    case io::SensorKind::kIns:
      return &setup_calibrate_ins_command;
    case io::SensorKind::kLidar:
      return &setup_calibrate_lidar_command;
    case io::SensorKind::kRadar:
      return &setup_calibrate_radar_command;
    case io::SensorKind::kCamera:
      return &setup_calibrate_camera_command;
  }
  throw std::logic_error("calibrate all: a sensor kind without a command");
}

// Runs `x2car calibrate <kind> <line>` in this process; returns its exit code (0 or 1; input
// errors propagate as exceptions, exit 2).
int run_sensor_command(io::SensorKind kind, std::vector<std::string> line) {
  CLI::App command;
  const RunCommand run = setup_for(kind)(command);
  std::ranges::reverse(line);  // CLI11 takes the arguments last first
  command.parse(line);
  return run();
}

struct SensorRun {
  io::DriveSensor sensor;
  CalibrationResult result;
  io::Json json;  // the sensor's own result file, as written
};

std::string angle_cell(const std::optional<double>& estimate_rad,
                       const std::optional<double>& truth_rad) {
  if (!estimate_rad) return "—";
  std::string cell = fmt::format("{:.3f}", deg_from_rad(*estimate_rad));
  if (truth_rad) {
    cell += fmt::format(" ({:+.3f})", deg_from_rad(wrap_angle(*estimate_rad - *truth_rad)));
  }
  return cell;
}

// One line per sensor: status and angles [deg], each with its error against the truth in
// parentheses when the folder has a ground_truth.yaml holding the sensor.
std::string summary_table(const std::vector<SensorRun>& runs,
                          const std::optional<io::GroundTruth>& truth) {
  std::string text = fmt::format("{:<12} {:<18} {:>18} {:>18} {:>18}\n", "sensor", "status",
                                 "roll [deg]", "pitch [deg]", "yaw [deg]");
  for (const SensorRun& run : runs) {
    const std::optional<io::SensorMounting> mounting =
        truth ? io::find_mounting(*truth, run.sensor.name) : std::nullopt;
    const auto true_angle = [&](double EulerAngles::*angle) -> std::optional<double> {
      if (!mounting) return std::nullopt;
      return mounting->rotation.*angle;
    };
    text += fmt::format("{:<12} {:<18} {:>18} {:>18} {:>18}\n", run.sensor.name,
                        to_string(run.result.status),
                        angle_cell(run.result.roll, true_angle(&EulerAngles::roll)),
                        angle_cell(run.result.pitch, true_angle(&EulerAngles::pitch)),
                        angle_cell(run.result.yaw, true_angle(&EulerAngles::yaw)));
  }
  if (truth) text += "(in parentheses: the error against ground_truth.yaml)\n";
  return text;
}

void write_outputs(const std::vector<SensorRun>& runs, const OutputArguments& output) {
  if (!output.json_path.empty()) {
    io::Json all = io::Json::object();
    for (const SensorRun& run : runs) all[run.sensor.name] = run.json;
    io::write_text_file(output.json_path, all.dump(2) + "\n");
    spdlog::info("wrote {}", output.json_path);
  }
  std::vector<Extrinsic> extrinsics;
  std::string notes;
  for (const SensorRun& run : runs) {
    if (!run.result.ok()) continue;
    extrinsics.push_back(io::extrinsic_from_result(run.result, "base_link", run.sensor.name));
    const std::vector<std::string> parts = io::unestimated_parts(run.result);
    if (!parts.empty()) {
      notes += fmt::format("x2car did not estimate these parts of {}; they are written as 0: {}\n",
                           run.sensor.name, fmt::join(parts, ", "));
    }
  }
  if (extrinsics.empty()) {
    if (!output.yaml_path.empty() || !output.urdf_path.empty()) {
      spdlog::warn("no sensor calibrated: no mounting to write to the YAML/URDF files");
    }
    return;
  }
  const auto commented = [&notes](const std::string& open, const std::string& close) {
    std::string text;
    for (const io::TextLine& line : io::split_lines(notes)) {
      text += open + std::string(line.text) + close + "\n";
    }
    return text;
  };
  if (!output.yaml_path.empty()) {
    io::write_text_file(output.yaml_path, commented("# ", "") + io::format_autoware(extrinsics));
  }
  if (!output.urdf_path.empty()) {
    std::string urdf = commented("<!-- ", " -->");
    for (const Extrinsic& extrinsic : extrinsics) urdf += io::format_urdf(extrinsic);
    io::write_text_file(output.urdf_path, urdf);
  }
}

int run_calibrate_all(const CalibrateAllArguments& arguments) {
  check_output_arguments(arguments.output, {{{"--input", arguments.input_path}}});
  const io::DriveFolder drive = io::bag_container_of(arguments.input_path)
                                    ? io::find_bag_sensors(arguments.input_path)
                                    : io::find_drive_sensors(arguments.input_path);
  std::optional<io::GroundTruth> truth;
  if (drive.ground_truth) truth = io::read_ground_truth(*drive.ground_truth);
  const ScratchFolder scratch;
  // Every sensor as its own task (each calibrator is parallel inside as well: the LiDAR's
  // odometry and the camera's frames then share the cores), its summary captured and printed in
  // the sensors' order; an input error of any ends the run (exit 2) once all have stopped.
  struct SensorTask {
    fs::path json;
    std::vector<std::string> line;
    std::ostringstream output;
    int exit_code = kExitOk;
  };
  std::vector<SensorTask> tasks(drive.sensors.size());
  for (std::size_t i = 0; i < drive.sensors.size(); ++i) {
    tasks[i].json = scratch.path() / (drive.sensors[i].name + ".json");
    tasks[i].line = sensor_arguments(drive.sensors[i], drive, arguments, tasks[i].json);
  }
  ProgressBar progress("sensors", spdlog::should_log(spdlog::level::info));
  std::size_t done = 0;
  std::mutex progress_mutex;  // the bar draws from one task at a time
  tbb::task_group group;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    group.run([&, i] {
      {
        const CapturedCommandOutput capture(tasks[i].output);
        tasks[i].exit_code = run_sensor_command(drive.sensors[i].kind, tasks[i].line);
      }
      const std::lock_guard lock(progress_mutex);
      progress.update(++done, tasks.size());
    });
  }
  group.wait();
  progress.finish();
  std::vector<SensorRun> runs;
  int exit_code = kExitOk;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const io::DriveSensor& sensor = drive.sensors[i];
    std::cout << fmt::format("== {} ({}, {})\n", sensor.name, io::to_string(sensor.kind),
                             sensor.input.string())
              << tasks[i].output.str();
    if (tasks[i].exit_code != kExitOk) exit_code = kExitInsufficientData;
    io::Json result = io::Json::parse(io::read_text_file(tasks[i].json));
    runs.push_back(
        {sensor, io::result_from_json(result, tasks[i].json.string()), std::move(result)});
  }
  std::cout << "\n" << summary_table(runs, truth);
  write_outputs(runs, arguments.output);
  if (!arguments.output.report_path.empty()) {
    report::ReportInput input{
        path_title(drive.root), "x2car calibrate all --input " + arguments.input_path, {}};
    for (const SensorRun& run : runs) {
      input.sensors.push_back(drive_report_sensor(run.sensor, run.result, truth));
    }
    write_report(arguments.output.report_path, input);
  }
  return exit_code;
}

}  // namespace

RunCommand setup_calibrate_all_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateAllArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "A drive folder as x2car simulate writes it (ins/novatel_enu.csv, lidar*/, "
                  "radar*/, camera*/), any folder with an x2car.yaml manifest naming each "
                  "sensor's type and input (docs/formats.md), or a bag (MCAP, ROS 1 .bag, ROS 2 "
                  "bag folder): a sensor per topic a calibrator reads")
      ->type_name("DIR|BAG")
      ->required();
  add_output_options(command, arguments->output);
  command.footer(
      "Each sensor runs as its own 'x2car calibrate <kind>' with that command's defaults; the "
      "radars and the camera take the drive's GNSS/INS log. --out writes one JSON keyed by "
      "sensor, --yaml and --urdf every sensor that calibrated, --report one HTML report of all. "
      "Exit 0 when all calibrated, 1 when "
      "some had too little data (the rest still written), 2 on bad input.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate all --input drive --out all.json --yaml sensor_kit_calibration.yaml");
  return [arguments] { return run_calibrate_all(*arguments); };
}

}  // namespace x2car::cli
