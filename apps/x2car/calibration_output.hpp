// What every `x2car calibrate SENSOR` does after its calibrator ran: print the result for a person,
// write it where asked (JSON, Autoware YAML, URDF) and turn its status into the exit code.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "apps/x2car/output_paths.hpp"
#include "x2car/camera/frame_views.hpp"
#include "x2car/core/calibration_result.hpp"

namespace x2car::cli {

struct OutputArguments {
  std::string json_path;    // --out: the result JSON (DESIGN §6)
  std::string yaml_path;    // --yaml: Autoware sensor_kit_calibration.yaml style
  std::string urdf_path;    // --urdf: a URDF joint
  std::string report_path;  // --report: the HTML report (x2car/report/report.hpp)
  bool without_series = false;
  bool reproducible = false;  // --reproducible: no wall time in the JSON, so runs compare equal
};

void add_output_options(CLI::App& command, OutputArguments& arguments);

// Checks --out, --yaml and --urdf before the calibration runs (output_paths.hpp): each must be
// writable and none may be one of `inputs`. Throws std::invalid_argument.
void check_output_arguments(const OutputArguments& arguments, std::span<const NamedPath> inputs);

// What a single calibration's --report shows beside the result.
struct ReportContext {
  std::string title;                      // the input's name
  std::string command;                    // the command line, in the page's footer
  std::vector<camera::FrameView> frames;  // a camera's sample frames
};

// The context of `x2car calibrate <kind> --input <input_path>`.
ReportContext report_context(const std::string& kind, const std::string& input_path);

// Prints the summary to stdout, writes the files (the YAML and URDF only for an ok result, the
// report whatever the status) and returns kExitOk or kExitInsufficientData.
int finish_calibration(const CalibrationResult& result, const OutputArguments& arguments,
                       const ReportContext& report = {});

// "yaw 2.013 deg +- 0.004" lines, unobserved angles as "not observable".
std::string format_result_summary(const CalibrationResult& result);

}  // namespace x2car::cli
