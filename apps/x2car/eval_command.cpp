// x2car eval: the paper's evaluation protocol on a drive folder (x2car/eval/segments.hpp): each
// sensor calibrated on the whole log and on every segment of a minute, the segments' spread over
// all and over straight driving, the share that gave an estimate, the time per segment, and the
// errors against ground_truth.yaml when the folder has one.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "apps/x2car/camera_inputs.hpp"
#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/output_paths.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/report_output.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/camera/bag_frames.hpp"
#include "x2car/camera/camera_frames.hpp"
#include "x2car/camera/video_frames.hpp"
#include "x2car/core/error.hpp"
#include "x2car/eval/eval_json.hpp"
#include "x2car/eval/segments.hpp"
#include "x2car/ins/ins_calibration.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/drive_folder.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/image_folder.hpp"
#include "x2car/io/ins_log.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/lidar/bag_sweeps.hpp"
#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/sweep_folder.hpp"
#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;

struct EvalArguments {
  std::string input_path;
  std::string sensor = "all";
  double segment_s = eval::SegmentOptions{}.segment_s;
  std::string json_path;
  std::string report_path;
};

// A sensor and its evaluation: the whole log's result and its segments'.
struct SensorEval {
  io::DriveSensor sensor;
  eval::SensorEvaluation evaluation;
};

// A bar over a sensor's segments on stderr (only when it is a terminal), done when the last ends.
std::function<void(std::size_t, std::size_t)> segment_progress(const io::DriveSensor& sensor) {
  auto bar = std::make_shared<ProgressBar>(sensor.name + " segments",
                                           spdlog::should_log(spdlog::level::info));
  return [bar](std::size_t done, std::size_t total) {
    bar->update(done, total);
    if (done == total) bar->finish();
  };
}

// The indices [first, last) of the sorted `times` inside the span: a segment's sweeps or frames.
std::pair<std::ptrdiff_t, std::ptrdiff_t> indices_within(const std::vector<double>& times,
                                                         const eval::TimeSpan& span) {
  return {std::ranges::lower_bound(times, span.start_s) - times.begin(),
          std::ranges::lower_bound(times, span.end_s) - times.begin()};
}

template <typename Item>
std::vector<Item> within(const std::vector<Item>& items, const eval::TimeSpan& span) {
  std::vector<Item> inside;
  for (const Item& item : items) {
    if (span.contains(item.time)) inside.push_back(item);
  }
  return inside;
}

SensorEval eval_ins(const io::DriveSensor& sensor, const std::vector<io::InsRecord>& records,
                    const eval::SegmentOptions& options, bool whole_series) {
  ins::InsCalibrationOptions calibration;
  calibration.keep_series = whole_series;  // the report's evidence
  SensorEval result{sensor, {ins::calibrate_ins(records, calibration), {}}};
  calibration.keep_series = false;
  if (records.empty()) return result;
  result.evaluation.segments = eval::calibrate_segments(
      eval::cut_into_segments(records.front().time, records.back().time, options),
      [&](const eval::TimeSpan& span) {
        return ins::calibrate_ins(within(records, span), calibration);
      },
      records, true, options, segment_progress(sensor));
  return result;
}

SensorEval eval_radar(const io::DriveSensor& sensor, const io::InsLog& ins_log,
                      const eval::SegmentOptions& options) {
  io::RadarReadOptions read_options;
  read_options.topic = sensor.topic;  // a bag's
  const io::RadarLog radar_log = io::read_radar(sensor.input, read_options);
  // The radar's times on the GNSS/INS log's clock.
  const std::vector<io::RadarDetection> detections =
      radar::detections_on_ins_clock(radar_log, ins_log);
  // With what a manifest says of the radar, as `calibrate all` runs it.
  radar::RadarCalibrationOptions calibration;
  if (sensor.lever_arm_m) {
    calibration.lever_arm_in_vehicle =
        Eigen::Vector2d((*sensor.lever_arm_m)[0], (*sensor.lever_arm_m)[1]);
  }
  if (sensor.nominal_yaw_deg) {
    calibration.velocity.nominal_yaw = rad_from_deg(*sensor.nominal_yaw_deg);
  }
  SensorEval result{sensor, {radar::calibrate_radar(detections, ins_log.records, calibration), {}}};
  if (detections.empty()) return result;
  result.evaluation.segments = eval::calibrate_segments(
      eval::cut_into_segments(detections.front().time, detections.back().time, options),
      [&](const eval::TimeSpan& span) {
        return radar::calibrate_radar(within(detections, span), ins_log.records, calibration);
      },
      ins_log.records, true, options, segment_progress(sensor));
  return result;
}

SensorEval eval_lidar(const io::DriveSensor& sensor, std::span<const io::InsRecord> ins,
                      const eval::SegmentOptions& options, bool whole_series) {
  const lidar::SweepSource source =
      io::bag_container_of(sensor.input)
          ? lidar::sweeps_from_bag(sensor.input, {.topic = sensor.topic}).source
          : lidar::sweep_source_from(lidar::list_sweeps(sensor.input));
  lidar::LidarCalibrationOptions calibration;
  calibration.keep_series = whole_series;
  SensorEval result{sensor, {lidar::calibrate_lidar(source, calibration), {}}};
  calibration.keep_series = false;
  if (source.times.empty()) return result;
  // The sweeps of each segment, read through the folder's own reader.
  const auto segment_source = [&source](const eval::TimeSpan& span) {
    const auto [first, last] = indices_within(source.times, span);
    lidar::SweepSource part;
    part.times.assign(source.times.begin() + first, source.times.begin() + last);
    part.read = [&source, first](std::size_t index) {
      return source.read(static_cast<std::size_t>(first) + index);
    };
    return part;
  };
  // The LiDAR's pipeline is parallel inside: its segments run one after the other.
  result.evaluation.segments = eval::calibrate_segments(
      eval::cut_into_segments(source.times.front(), source.times.back(), options),
      [&](const eval::TimeSpan& span) {
        return lidar::calibrate_lidar(segment_source(span), calibration);
      },
      ins, false, options, segment_progress(sensor));
  return result;
}

SensorEval eval_camera(const io::DriveSensor& sensor, const std::optional<fs::path>& ins_path,
                       const std::optional<std::string>& ins_topic,
                       const std::optional<io::InsLog>& ins_log,
                       const eval::SegmentOptions& options, bool whole_series) {
  IntrinsicsSource intrinsics_source;
  if (sensor.intrinsics) intrinsics_source.intrinsics_path = sensor.intrinsics->string();
  io::ImageFolder folder;  // outlives the frames that read from it
  camera::CameraFrameSource source;
  std::optional<core::CameraIntrinsics> bag_intrinsics;
  if (io::bag_container_of(sensor.input)) {
    camera::BagFrames bag = camera::camera_frames_from_bag(sensor.input, {.topic = sensor.topic});
    source = std::move(bag.source);
    bag_intrinsics = bag.intrinsics;
  } else if (camera::is_video_file(sensor.input)) {
    camera::VideoFrames video = camera::camera_frames_from_video(sensor.input);
    for (const std::string& note : video.notes) spdlog::warn("{}", note);
    source = std::move(video.source);
  } else {
    folder = io::list_images(sensor.input);
    source = camera::camera_frames_from(folder);
    // KITTI raw's camera X takes the _0X keys of calib_cam_to_cam.txt.
    intrinsics_source.camera_index = folder.kitti_camera_index;
  }
  // A manifest's intrinsics win over the bag's CameraInfo, as --intrinsics does.
  const core::CameraIntrinsics intrinsics =
      bag_intrinsics && !sensor.intrinsics
          ? *bag_intrinsics
          : find_camera_intrinsics(sensor.input.string(), intrinsics_source);
  if (ins_path) {
    source.motion = camera_motion_from_log(ins_path->string(), source, ins_topic.value_or(""));
  }
  camera::CameraCalibrationOptions calibration;
  calibration.keep_series = whole_series;
  SensorEval result{sensor, {camera::calibrate_camera(source, intrinsics, calibration), {}}};
  calibration.keep_series = false;
  if (source.times.empty()) return result;
  // The frames of each segment, decoded through the folder's own reader.
  const auto segment_source = [&source](const eval::TimeSpan& span) {
    const auto [first, last] = indices_within(source.times, span);
    camera::CameraFrameSource part;
    part.times.assign(source.times.begin() + first, source.times.begin() + last);
    const auto at = [first](std::size_t index) { return static_cast<std::size_t>(first) + index; };
    part.read = [&source, at](std::size_t index) { return source.read(at(index)); };
    part.name = [&source, at](std::size_t index) { return source.name(at(index)); };
    if (!source.motion.empty()) {
      part.motion.assign(source.motion.begin() + first, source.motion.begin() + last);
    }
    return part;
  };
  // Straight or not by the GNSS/INS heading, on the frames' clock: frames in Unix time (KITTI
  // raw, the simulator) meet the log's records shifted by its start, as for the motion gate.
  std::vector<io::InsRecord> ins;
  if (ins_log) {
    ins = ins_log->records;
    const bool unix_frames = source.times.front() > 1e8;
    if (unix_frames && ins_log->start_unix_time) {
      for (io::InsRecord& record : ins) record.time += *ins_log->start_unix_time;
    }
  }
  // The camera's pipeline is parallel inside: its segments run one after the other.
  result.evaluation.segments = eval::calibrate_segments(
      eval::cut_into_segments(source.times.front(), source.times.back(), options),
      [&](const eval::TimeSpan& span) {
        return camera::calibrate_camera(segment_source(span), intrinsics, calibration);
      },
      ins, false, options, segment_progress(sensor));
  return result;
}

std::optional<io::SensorMounting> true_mounting(const std::optional<io::GroundTruth>& truth,
                                                const std::string& name) {
  return truth ? io::find_mounting(*truth, name) : std::nullopt;
}

std::string degrees(const std::optional<double>& radians, const char* format = "{:.3f}") {
  return radians ? fmt::format(fmt::runtime(format), deg_from_rad(*radians)) : "—";
}

// The Table III-style lines of one sensor.
std::string format_sensor_table(const SensorEval& run, const eval::SegmentSummary& summary,
                                const std::optional<io::SensorMounting>& mounting) {
  const std::optional<EulerAngles> truth =
      mounting ? std::optional(mounting->rotation) : std::nullopt;
  std::string text = fmt::format(
      "== {}: {} segments, {} gave an estimate ({:.0f} %), {:.2f} s per segment; whole log: {}\n",
      run.sensor.name, summary.segments, summary.with_estimate,
      summary.segments ? 100.0 * summary.with_estimate / summary.segments : 0.0,
      summary.mean_seconds, to_string(run.evaluation.whole_log.status));
  text += fmt::format("{:<6} {:>10} {:>10} {:>12} {:>12} {:>14} {:>14}\n", "[deg]", "whole log",
                      "error", "segments", "std (all)", "std (straight)", "max |seg err|");
  const auto row = [&](const char* name, std::optional<double> CalibrationResult::*estimate,
                       const eval::AngleSpread& spread, double EulerAngles::*angle) {
    const std::optional<double>& whole = run.evaluation.whole_log.*estimate;
    std::optional<double> error;
    std::optional<double> worst;
    if (truth) {
      if (whole) error = wrap_angle(*whole - (*truth).*angle);
      for (const eval::SegmentResult& segment : run.evaluation.segments) {
        const std::optional<double>& value = segment.result.*estimate;
        if (!segment.result.ok() || !value) continue;
        const double miss = std::abs(wrap_angle(*value - (*truth).*angle));
        worst = std::max(worst.value_or(0.0), miss);
      }
    }
    if (!whole && spread.count == 0) return;
    text += fmt::format("{:<6} {:>10} {:>10} {:>12} {:>12} {:>14} {:>14}\n", name, degrees(whole),
                        degrees(error, "{:+.3f}"),
                        fmt::format("{} of {}", spread.count, summary.segments),
                        degrees(spread.std_all),
                        fmt::format("{} ({})", degrees(spread.std_straight), spread.straight_count),
                        degrees(worst));
  };
  row("roll", &CalibrationResult::roll, summary.roll, &EulerAngles::roll);
  row("pitch", &CalibrationResult::pitch, summary.pitch, &EulerAngles::pitch);
  row("yaw", &CalibrationResult::yaw, summary.yaw, &EulerAngles::yaw);
  // The LiDAR's height above the road [m], as the paper's Table III has it.
  if (run.evaluation.whole_log.z || summary.z.count > 0) {
    const auto metres = [](const std::optional<double>& value, const char* format = "{:.4f}") {
      return value ? fmt::format(fmt::runtime(format), *value) : std::string("—");
    };
    std::optional<double> error;
    std::optional<double> worst;
    if (mounting) {
      const double true_z = mounting->translation.z();
      if (run.evaluation.whole_log.z) error = *run.evaluation.whole_log.z - true_z;
      for (const eval::SegmentResult& segment : run.evaluation.segments) {
        if (!segment.result.ok() || !segment.result.z) continue;
        worst = std::max(worst.value_or(0.0), std::abs(*segment.result.z - true_z));
      }
    }
    text += fmt::format(
        "{:<6} {:>10} {:>10} {:>12} {:>12} {:>14} {:>14}\n", "z [m]",
        metres(run.evaluation.whole_log.z), metres(error, "{:+.4f}"),
        fmt::format("{} of {}", summary.z.count, summary.segments), metres(summary.z.std_all),
        fmt::format("{} ({})", metres(summary.z.std_straight), summary.z.straight_count),
        metres(worst));
  }
  return text;
}

int run_eval(const EvalArguments& arguments) {
  if (!arguments.json_path.empty()) {
    const std::array<NamedPath, 1> outputs = {{{"--out", arguments.json_path}}};
    const std::array<NamedPath, 1> inputs = {{{"--input", arguments.input_path}}};
    check_output_files(outputs, inputs);
  }
  const bool with_report = !arguments.report_path.empty();
  if (with_report) {
    const std::array<NamedPath, 1> outputs = {{{"--report", arguments.report_path}}};
    const std::array<NamedPath, 2> inputs = {
        {{"--input", arguments.input_path}, {"--out", arguments.json_path}}};
    check_output_files(outputs, inputs);
  }
  eval::SegmentOptions options;
  options.segment_s = arguments.segment_s;
  options.Check();
  const io::DriveFolder drive = io::bag_container_of(arguments.input_path)
                                    ? io::find_bag_sensors(arguments.input_path)
                                    : io::find_drive_sensors(arguments.input_path);
  std::optional<io::GroundTruth> truth;
  if (drive.ground_truth) truth = io::read_ground_truth(*drive.ground_truth);
  std::optional<io::InsLog> ins_log;
  if (drive.ins_log) {
    io::InsReadOptions ins_options;
    ins_options.topic = drive.ins_topic;
    ins_log = io::read_ins_log(*drive.ins_log, ins_options);
  }
  const std::span<const io::InsRecord> ins =
      ins_log ? std::span<const io::InsRecord>(ins_log->records) : std::span<const io::InsRecord>();

  std::vector<SensorEval> runs;
  bool found = false;
  for (const io::DriveSensor& sensor : drive.sensors) {
    if (arguments.sensor != "all" && arguments.sensor != sensor.name) continue;
    found = true;
    spdlog::info("evaluating {} in segments of {:g} s", sensor.name, options.segment_s);
    switch (sensor.kind) {
      case io::SensorKind::kIns:
        runs.push_back(eval_ins(sensor, ins_log->records, options, with_report));
        break;
      case io::SensorKind::kRadar:
        if (!ins_log) {
          throw InputError(sensor.input.string(), "a radar needs the drive's ins/novatel_enu.csv");
        }
        runs.push_back(eval_radar(sensor, *ins_log, options));
        break;
      case io::SensorKind::kLidar:
        runs.push_back(eval_lidar(sensor, ins, options, with_report));
        break;
      case io::SensorKind::kCamera:
        runs.push_back(
            eval_camera(sensor, drive.ins_log, drive.ins_topic, ins_log, options, with_report));
        break;
    }
  }
  if (!found) {
    std::vector<std::string> names;
    for (const io::DriveSensor& sensor : drive.sensors) names.push_back(sensor.name);
    throw InputError(
        arguments.input_path, 0, "--sensor",
        fmt::format("no sensor '{}'; the folder holds: {}", arguments.sensor, io::join(names)));
  }
  io::Json all = io::Json::object();
  bool every_whole_ok = true;
  for (const SensorEval& run : runs) {
    const eval::SegmentSummary summary = eval::summarise_segments(run.evaluation.segments);
    std::cout << format_sensor_table(run, summary, true_mounting(truth, run.sensor.name)) << "\n";
    all[run.sensor.name] =
        eval::evaluation_to_json(run.evaluation, {.include_series = false, .include_timing = true});
    every_whole_ok = every_whole_ok && run.evaluation.whole_log.ok();
  }
  if (truth) std::cout << "(error: the whole log's estimate minus ground_truth.yaml)\n";
  if (!arguments.json_path.empty()) {
    io::write_text_file(arguments.json_path, all.dump(2) + "\n");
    spdlog::info("wrote {}", arguments.json_path);
  }
  if (with_report) {
    report::ReportInput input{
        path_title(drive.root), "x2car eval --input " + arguments.input_path, {}};
    for (const SensorEval& run : runs) {
      report::ReportSensor entry = drive_report_sensor(run.sensor, run.evaluation.whole_log, truth);
      entry.evaluation = run.evaluation;
      input.sensors.push_back(std::move(entry));
    }
    write_report(arguments.report_path, input);
  }
  return every_whole_ok ? kExitOk : kExitInsufficientData;
}

}  // namespace

RunCommand setup_eval_command(CLI::App& command) {
  auto arguments = std::make_shared<EvalArguments>();
  command
      .add_option("-i,--input", arguments->input_path,
                  "A drive folder as x2car simulate writes it (ins/, lidar*/, radar*/, camera*/), "
                  "a folder with an x2car.yaml manifest, or a bag (a sensor per topic)")
      ->type_name("DIR|BAG")
      ->required();
  command.add_option("--sensor", arguments->sensor, "The sensor folder's name, or all")
      ->type_name("NAME")
      ->capture_default_str();
  command.add_option("--segment", arguments->segment_s, "Segment length [s] (the paper's minute)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command.add_option("-o,--out", arguments->json_path,
                     "Write the whole-log and per-segment results and the spreads as JSON");
  command
      .add_option("--report", arguments->report_path,
                  "Also write the HTML report: each sensor's whole-log result with its evidence "
                  "and its segments' estimates (x2car report)")
      ->type_name("FILE");
  command.footer(
      "The paper's protocol (its Table III): each sensor calibrated on the whole log and on each "
      "segment, with each calibrator's defaults; the spread of the segments' estimates over all "
      "and over straight segments (heading within 10 deg), the share that gave one, the time per "
      "segment, and the errors against ground_truth.yaml when present. Exit 1 when a sensor's "
      "whole log gave no estimate.\n"
      "\n"
      "Example:\n"
      "  x2car eval --input drive --sensor all --out eval.json");
  return [arguments] { return run_eval(*arguments); };
}

}  // namespace x2car::cli
