// x2car report: the HTML report (x2car/report/report.hpp) of results already written, from
// `calibrate ... --out` and/or `eval --out`, with the truth and a camera's frames from the drive
// folder when it is given.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/output_paths.hpp"
#include "apps/x2car/report_output.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/eval/eval_json.hpp"
#include "x2car/io/drive_folder.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;

struct ReportArguments {
  std::string result_path;
  std::string eval_path;
  std::string input_path;
  std::string truth_path;
  std::string out_path;
};

io::Json read_json(const std::string& path) {
  const std::string text = io::read_text_file(path);
  try {
    return io::Json::parse(text);
  } catch (const io::Json::parse_error& error) {
    throw InputError(path, fmt::format("not JSON: {}", error.what()));
  }
}

std::map<std::string, eval::SensorEvaluation> read_evaluations(const std::string& path) {
  const io::Json json = read_json(path);
  if (!json.is_object() || json.empty()) {
    throw InputError(path, "expected x2car eval's JSON: an object keyed by sensor");
  }
  std::map<std::string, eval::SensorEvaluation> evaluations;
  for (const auto& [name, value] : json.items()) {
    evaluations[name] = eval::evaluation_from_json(value, fmt::format("{} ({})", path, name));
  }
  return evaluations;
}

// The drive's sensor of this name, else the one sensor of the result's kind.
const io::DriveSensor* drive_sensor(const io::DriveFolder& drive, const std::string& name,
                                    const CalibrationResult& result) {
  const io::DriveSensor* same_kind = nullptr;
  int kind_count = 0;
  for (const io::DriveSensor& sensor : drive.sensors) {
    if (sensor.name == name) return &sensor;
    if (io::to_string(sensor.kind) == result.sensor) {
      same_kind = &sensor;
      ++kind_count;
    }
  }
  return kind_count == 1 ? same_kind : nullptr;
}

int run_report(const ReportArguments& arguments) {
  if (arguments.result_path.empty() && arguments.eval_path.empty()) {
    throw std::invalid_argument("give --result (calibrate --out) or --eval (eval --out), or both");
  }
  const std::array<NamedPath, 1> outputs = {{{"--out", arguments.out_path}}};
  const std::array<NamedPath, 4> inputs = {{{"--result", arguments.result_path},
                                            {"--eval", arguments.eval_path},
                                            {"--input", arguments.input_path},
                                            {"--truth", arguments.truth_path}}};
  check_output_files(outputs, inputs);

  std::vector<io::NamedResult> results;
  if (!arguments.result_path.empty()) {
    results =
        io::parse_named_results(io::read_text_file(arguments.result_path), arguments.result_path);
  }
  std::map<std::string, eval::SensorEvaluation> evaluations;
  if (!arguments.eval_path.empty()) evaluations = read_evaluations(arguments.eval_path);
  // Sensors evaluated but not in --result: their whole-log result stands in (without series).
  for (const auto& [name, evaluation] : evaluations) {
    const bool listed =
        std::ranges::any_of(results, [&](const io::NamedResult& r) { return r.name == name; });
    if (!listed) results.push_back({name, evaluation.whole_log});
  }

  std::optional<io::DriveFolder> drive;
  if (!arguments.input_path.empty()) drive = io::find_drive_sensors(arguments.input_path);
  std::optional<io::GroundTruth> truth;
  if (!arguments.truth_path.empty()) {
    truth = io::read_ground_truth(arguments.truth_path);
  } else if (drive && drive->ground_truth) {
    truth = io::read_ground_truth(*drive->ground_truth);
  }

  report::ReportInput input;
  const std::string source = !arguments.input_path.empty()    ? arguments.input_path
                             : !arguments.result_path.empty() ? arguments.result_path
                                                              : arguments.eval_path;
  input.title = path_title(source);
  input.command = "x2car report";
  for (const auto& [flag, path] : inputs) {
    if (!path.empty()) input.command += fmt::format(" {} {}", flag, path);
  }
  for (auto& [name, result] : results) {
    const io::DriveSensor* sensor = drive ? drive_sensor(*drive, name, result) : nullptr;
    report::ReportSensor entry =
        sensor ? drive_report_sensor(*sensor, std::move(result), truth)
               : report::ReportSensor{name, std::move(result), std::nullopt, std::nullopt, {}};
    if (!sensor && truth) entry.truth = io::find_mounting(*truth, name);
    if (const auto found = evaluations.find(name); found != evaluations.end()) {
      entry.evaluation = found->second;
    }
    input.sensors.push_back(std::move(entry));
  }
  write_report(arguments.out_path, input);
  std::cout << arguments.out_path << "\n";
  return kExitOk;
}

}  // namespace

RunCommand setup_report_command(CLI::App& command) {
  auto arguments = std::make_shared<ReportArguments>();
  command
      .add_option("-r,--result", arguments->result_path,
                  "A result JSON: one sensor's (calibrate SENSOR --out) or every sensor's "
                  "(calibrate all --out)")
      ->type_name("FILE");
  command.add_option("-e,--eval", arguments->eval_path, "x2car eval's JSON (eval --out)")
      ->type_name("FILE");
  command
      .add_option("-i,--input", arguments->input_path,
                  "The drive folder the results came from: its ground_truth.yaml gives the errors "
                  "and a camera's images the frames shown")
      ->type_name("DIR");
  command
      .add_option("--truth", arguments->truth_path,
                  "A ground_truth.yaml (default: the drive folder's, when there is one)")
      ->type_name("FILE");
  command.add_option("-o,--out", arguments->out_path, "The report to write (.html)")
      ->type_name("FILE")
      ->required();
  command.footer(
      "One self-contained HTML file (charts inlined, no network needed): each sensor's result, "
      "the evidence behind it, the segments of an evaluation, a camera's frames and a view to "
      "adjust its angles by eye. calibrate and eval write the same with --report FILE.\n"
      "\n"
      "Example:\n"
      "  x2car report --result all.json --eval eval.json --input drive --out report.html");
  return [arguments] { return run_report(*arguments); };
}

}  // namespace x2car::cli
