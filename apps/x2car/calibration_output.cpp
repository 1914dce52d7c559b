#include "apps/x2car/calibration_output.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "apps/x2car/command_output.hpp"
#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/report_output.hpp"
#include "x2car/io/extrinsic_formats.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

// `missing` says why an angle has no value.
std::string angle_line(const char* name, const std::optional<double>& value,
                       const std::optional<double>& standard_error, const char* missing) {
  if (!value) return fmt::format("  {:<6} {}\n", name, missing);
  return fmt::format("  {:<6} {:9.4f} deg  +- {:.4f} deg (standard error)\n", name,
                     deg_from_rad(*value), deg_from_rad(standard_error.value_or(0.0)));
}

// The log's own mounting (a bag's tf_static) beside the calibrated one: before -> after.
std::string prior_lines(const CalibrationResult& result) {
  const MountingPrior& prior = *result.prior;
  std::string text = fmt::format(
      "  prior {} -> {} ({}): roll {:.4f} pitch {:.4f} yaw {:.4f} deg at {:.3f} {:.3f} {:.3f} m\n",
      prior.parent, prior.child, prior.source, deg_from_rad(prior.angles.roll),
      deg_from_rad(prior.angles.pitch), deg_from_rad(prior.angles.yaw), prior.translation.x(),
      prior.translation.y(), prior.translation.z());
  std::string changes;
  const auto change = [&](const char* name, const std::optional<double>& after, double before) {
    if (!after) return;
    changes += fmt::format(" {} {:.4f} -> {:.4f} ({:+.4f}),", name, deg_from_rad(before),
                           deg_from_rad(*after), deg_from_rad(wrap_angle(*after - before)));
  };
  change("roll", result.roll, prior.angles.roll);
  change("pitch", result.pitch, prior.angles.pitch);
  change("yaw", result.yaw, prior.angles.yaw);
  if (result.z) {
    changes += fmt::format(" z {:.4f} -> {:.4f} m ({:+.4f}),", prior.translation.z(), *result.z,
                           *result.z - prior.translation.z());
  }
  if (!changes.empty()) {
    changes.pop_back();
    text += "  before -> after [deg]:" + changes + "\n";
  }
  return text;
}

std::string counts_line(const char* title, const std::map<std::string, std::int64_t>& counts) {
  std::string line = fmt::format("  {}:", title);
  for (const auto& [name, count] : counts) line += fmt::format(" {} {},", name, count);
  if (!counts.empty()) line.pop_back();
  return line + "\n";
}

}  // namespace

void add_output_options(CLI::App& command, OutputArguments& arguments) {
  command.add_option("-o,--out", arguments.json_path, "Write the result JSON to FILE")
      ->type_name("FILE");
  command
      .add_option("--yaml", arguments.yaml_path,
                  "Also write the mounting as Autoware sensor_kit_calibration.yaml")
      ->type_name("FILE");
  command.add_option("--urdf", arguments.urdf_path, "Also write the mounting as a URDF joint")
      ->type_name("FILE");
  command
      .add_option("--report", arguments.report_path,
                  "Also write the HTML report: the result, the evidence behind it as charts "
                  "(x2car report)")
      ->type_name("FILE");
  command.add_flag("--without-series", arguments.without_series,
                   "Leave the per-sample series out of the JSON (smaller file)");
  command.add_flag("--reproducible", arguments.reproducible,
                   "Leave the wall time ('seconds') out of the JSON, so that identical runs write "
                   "identical bytes");
}

void check_output_arguments(const OutputArguments& arguments, std::span<const NamedPath> inputs) {
  const NamedPath outputs[] = {{"--out", arguments.json_path},
                               {"--yaml", arguments.yaml_path},
                               {"--urdf", arguments.urdf_path},
                               {"--report", arguments.report_path}};
  check_output_files(outputs, inputs);
}

std::string format_result_summary(const CalibrationResult& result) {
  std::string text;
  if (!result.ok()) {
    const char* what = result.status == CalibrationStatus::kUnreliable
                           ? "unreliable, not a mounting"
                           : "insufficient data";
    text = fmt::format("{}: {}: {}\n", result.sensor, what, result.reason);
    // What could be estimated is still shown (the LiDAR's ground when only its yaw lacks data, the
    // angles of a fit that failed its checks); nothing is written as a mounting. Without any, the
    // counts still say why (every frame of a black video rejected as too_few_lines).
    if (!result.roll && !result.pitch && !result.yaw && !result.z) {
      if (!result.support.empty()) text += counts_line("support", result.support);
      if (!result.rejections.empty()) text += counts_line("rejected", result.rejections);
      return text;
    }
    text += "  estimated so far (not a complete mounting):\n";
  } else {
    text += fmt::format("{}: vehicle_from_{} (method {}), {:.3f} s\n", result.sensor, result.sensor,
                        result.method.empty() ? "-" : result.method, result.seconds);
  }
  const char* missing = result.ok() ? "not observable by this method" : "not estimated";
  text += angle_line("roll", result.roll, result.roll_std, missing);
  text += angle_line("pitch", result.pitch, result.pitch_std, missing);
  text += angle_line("yaw", result.yaw, result.yaw_std, missing);
  // The radar velocity method's ego-speed scale (true speed / the GNSS/INS speed).
  for (const char* prefix : {"", "velocity_"}) {
    const auto scale = result.diagnostics.find(std::string(prefix) + "speed_scale");
    const auto scale_std = result.diagnostics.find(std::string(prefix) + "speed_scale_std");
    if (scale == result.diagnostics.end() || scale_std == result.diagnostics.end()) continue;
    text += fmt::format("  speed scale {:.4f} +- {:.4f} (true / GNSS/INS speed{})\n", scale->second,
                        scale_std->second, *prefix ? ", velocity method" : "");
    break;
  }
  if (result.z) {
    text += fmt::format("  {:<6} {:9.4f} m    +- {:.4f} m\n", "z", *result.z,
                        result.z_std.value_or(0.0));
  }
  if (result.prior) text += prior_lines(result);
  text += counts_line("support", result.support);
  text += counts_line("rejected", result.rejections);
  if (result.ok() && !result.reason.empty()) text += fmt::format("  note: {}\n", result.reason);
  return text;
}

ReportContext report_context(const std::string& kind, const std::string& input_path) {
  return {
      path_title(input_path), fmt::format("x2car calibrate {} --input {}", kind, input_path), {}};
}

int finish_calibration(const CalibrationResult& result, const OutputArguments& arguments,
                       const ReportContext& report) {
  command_output() << format_result_summary(result);
  // -v: the figures behind the estimate, which the summary leaves to the JSON.
  for (const auto& [name, value] : result.diagnostics) spdlog::debug("  {} = {:g}", name, value);
  if (!arguments.json_path.empty()) {
    io::write_result_json(
        arguments.json_path, result,
        {.include_series = !arguments.without_series, .include_timing = !arguments.reproducible});
    spdlog::info("wrote {}", arguments.json_path);
  }
  if (!arguments.report_path.empty()) {
    report::ReportInput input{report.title, report.command, {}};
    input.sensors.push_back({result.sensor, result, std::nullopt, std::nullopt, report.frames});
    write_report(arguments.report_path, input);
  }
  if (!result.ok()) {
    if (!arguments.yaml_path.empty() || !arguments.urdf_path.empty()) {
      spdlog::warn("no mounting to write to the YAML/URDF files: {}", result.reason);
    }
    return kExitInsufficientData;
  }
  if (!arguments.yaml_path.empty()) {
    io::write_text_file(arguments.yaml_path, io::format_result_autoware(result));
  }
  if (!arguments.urdf_path.empty()) {
    io::write_text_file(arguments.urdf_path, io::format_result_urdf(result));
  }
  return kExitOk;
}

}  // namespace x2car::cli
