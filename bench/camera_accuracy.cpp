// Camera calibration against the simulator's truth (issue 14, "Done when"): for each drive folder
// given (x2car simulate --sensors camera ...), the whole drive's angles and their errors, the share
// of frames used and why the others were not, and the spread of the angles over segments of
// --segment seconds (the paper's per-segment consistency). With the drive's camera/labels.csv (the
// simulator's per-frame truth) it also says where the error comes from, averaged over the frames in
// passing windows: the estimated road vanishing point against the true one [px] (the estimator's
// own error), the true road vanishing point against the car's forward one [px] (the body's pitch
// and heading in its lane), and the road's crossfall (the gravity horizon's angle against the
// road's) [deg], which the horizon of vertical edges cannot see.
//
//   x2car_camera_accuracy [--segment 60] [--window-frames 100] [--ins]
//                         [--estimator geometric|motion|auto] [--table FILE] DRIVE...
//
// --ins gates the frames by the drive's GNSS/INS log (DRIVE/ins/novatel_enu.csv: speed, yaw rate,
// acceleration), as `x2car calibrate camera --ins` does.
//
// Prints one block per drive and a summary (largest |error| and segment spread per angle, against
// the targets, and the coverage of the standard errors over every ok result, whole drives
// and segments: bench/coverage.hpp's check with as few runs as the drives give); --table appends
// one tab-separated row per drive. Exit 1 when a drive cannot be read.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "coverage.hpp"
#include "x2car/camera/camera_calibration.hpp"
#include "x2car/camera/camera_frames.hpp"
#include "x2car/camera/ins_motion.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/image_folder.hpp"
#include "x2car/io/ins_log.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

using namespace x2car;

struct Errors {
  double roll = NAN, pitch = NAN, yaw = NAN;  // [deg]
};

Errors errors_of(const CalibrationResult& result, const EulerAngles& truth) {
  Errors errors;
  if (result.roll) errors.roll = deg_from_rad(angle_difference(*result.roll, truth.roll));
  if (result.pitch) errors.pitch = deg_from_rad(angle_difference(*result.pitch, truth.pitch));
  if (result.yaw) errors.yaw = deg_from_rad(angle_difference(*result.yaw, truth.yaw));
  return errors;
}

// The frames of [begin, end) of `all` as their own source.
camera::CameraFrameSource slice(const camera::CameraFrameSource& all, std::size_t begin,
                                std::size_t end) {
  camera::CameraFrameSource part;
  part.times.assign(all.times.begin() + static_cast<std::ptrdiff_t>(begin),
                    all.times.begin() + static_cast<std::ptrdiff_t>(end));
  part.read = [&all, begin](std::size_t index) { return all.read(begin + index); };
  part.name = [&all, begin](std::size_t index) { return all.name(begin + index); };
  if (!all.motion.empty()) {
    part.motion.assign(all.motion.begin() + static_cast<std::ptrdiff_t>(begin),
                       all.motion.begin() + static_cast<std::ptrdiff_t>(end));
  }
  return part;
}

double spread(const std::vector<double>& values) {
  if (values.size() < 2) return NAN;
  double mean = 0.0;
  for (const double value : values) mean += value / static_cast<double>(values.size());
  double sum = 0.0;
  for (const double value : values) sum += (value - mean) * (value - mean);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

// camera/labels.csv as columns by name (empty cells NaN); empty when the file is absent.
std::map<std::string, std::vector<double>> read_labels(const std::string& path) {
  std::map<std::string, std::vector<double>> columns;
  std::ifstream file(path);
  std::string line;
  if (!file || !std::getline(file, line)) return columns;
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  while (std::getline(file, line)) {
    std::stringstream row(line);
    std::string cell;
    for (const std::string& name : names) {
      if (!std::getline(row, cell, ',')) cell.clear();
      columns[name].push_back(cell.empty() ? NAN : std::atof(cell.c_str()));
    }
  }
  return columns;
}

const Series* find_series(const CalibrationResult& result, const std::string& name) {
  for (const Series& series : result.series) {
    if (series.name == name) return &series;
  }
  return nullptr;
}

// Where the error comes from (the header's list), averaged over the frames in passing windows.
struct Diagnosis {
  int frames = 0;
  double vp_u_error_px = 0.0, vp_v_error_px = 0.0;  // estimated - true road VP
  double road_minus_forward_v_px = 0.0;             // true road VP - car's forward VP
  double crossfall_deg = 0.0;                       // gravity horizon angle - road horizon angle
};

Diagnosis diagnose(const CalibrationResult& result,
                   const std::map<std::string, std::vector<double>>& labels) {
  Diagnosis diagnosis;
  const Series* in_window = find_series(result, "in_window");
  const Series* vp_u = find_series(result, "road_vanishing_point_u");
  const Series* vp_v = find_series(result, "road_vanishing_point_v");
  if (labels.empty() || !in_window || !vp_u || !vp_v || in_window->time.empty()) return diagnosis;
  const std::vector<double>& frame_times = in_window->time;
  const std::size_t rows = labels.begin()->second.size();
  for (std::size_t k = 0; k < vp_u->time.size(); ++k) {
    // Frames are the labels' rows in order; find this estimate's frame by its time.
    const auto at = std::lower_bound(frame_times.begin(), frame_times.end(), vp_u->time[k]);
    const auto i = static_cast<std::size_t>(at - frame_times.begin());
    if (i >= rows || in_window->value[i] == 0.0) continue;
    const double road_u = labels.at("road_vp_u")[i], road_v = labels.at("road_vp_v")[i];
    if (!std::isfinite(road_u) || !std::isfinite(road_v)) continue;
    ++diagnosis.frames;
    diagnosis.vp_u_error_px += vp_u->value[k] - road_u;
    diagnosis.vp_v_error_px += vp_v->value[k] - road_v;
    diagnosis.road_minus_forward_v_px += road_v - labels.at("forward_vp_v")[i];
    diagnosis.crossfall_deg +=
        deg_from_rad(labels.at("level_horizon_angle")[i] - labels.at("road_horizon_angle")[i]);
  }
  if (diagnosis.frames > 0) {
    const double n = diagnosis.frames;
    diagnosis.vp_u_error_px /= n;
    diagnosis.vp_v_error_px /= n;
    diagnosis.road_minus_forward_v_px /= n;
    diagnosis.crossfall_deg /= n;
  }
  return diagnosis;
}

struct Summary {
  int drives = 0, failed = 0;
  Errors worst{0.0, 0.0, 0.0};
  Errors widest{0.0, 0.0, 0.0};
  double slowest_fps = INFINITY;
  // Every ok result (whole drives and segments) against its standard errors [deg].
  std::vector<bench::CoverageRun> roll_runs, pitch_runs, yaw_runs;
};

void add_coverage_runs(const std::string& label, const CalibrationResult& result,
                       const Errors& errors, Summary& summary) {
  if (!result.ok()) return;
  const auto add = [&label](std::vector<bench::CoverageRun>& runs, double error,
                            const std::optional<double>& standard_error) {
    if (std::isfinite(error) && standard_error) {
      runs.push_back({label, error, deg_from_rad(*standard_error)});
    }
  };
  add(summary.roll_runs, errors.roll, result.roll_std);
  add(summary.pitch_runs, errors.pitch, result.pitch_std);
  add(summary.yaw_runs, errors.yaw, result.yaw_std);
}

void keep_largest(double& largest, double value) {
  if (std::isfinite(value)) largest = std::max(largest, std::abs(value));
}

void run(const std::string& drive, double segment_s, bool with_ins,
         const camera::CameraCalibrationOptions& options, std::ofstream& table, Summary& summary) {
  const io::GroundTruth ground_truth = io::read_ground_truth(drive + "/ground_truth.yaml");
  const EulerAngles truth = ground_truth.vehicle_from_sensor.at("camera").rotation;
  const core::CameraIntrinsics intrinsics =
      io::read_camera_info_yaml(drive + "/camera/intrinsics.yaml");
  const io::ImageFolder folder = io::list_images(drive);
  camera::CameraFrameSource frames = camera::camera_frames_from(folder);
  if (with_ins) {
    // The simulator's NovAtel-style log carries GPS time, as the frames' timestamps.txt does.
    const io::InsLog log = io::read_ins_log(drive + "/ins/novatel_enu.csv");
    camera::InsMotionOptions motion_options;
    motion_options.ins_to_frame_offset_s = log.start_unix_time.value_or(0.0);
    frames.motion = camera::motion_from_ins(frames.times, log.records, motion_options);
  }
  const CalibrationResult whole = camera::calibrate_camera(frames, intrinsics, options);
  const Errors errors = errors_of(whole, truth);
  const auto support = [&whole](const char* key) {
    return whole.support.count(key) ? whole.support.at(key) : 0;
  };
  const double fps = static_cast<double>(frames.times.size()) / whole.seconds;
  fmt::print(
      "{} ({} {}x{}): {} error roll {:+.3f} pitch {:+.3f} yaw {:+.3f} deg; {} frames, {} in "
      "windows ({:.0f} %), {:.1f} frames/s {}\n",
      drive, ground_truth.scenario, intrinsics.width, intrinsics.height, to_string(whole.status),
      errors.roll, errors.pitch, errors.yaw, frames.times.size(), support("frames_in_windows"),
      100.0 * static_cast<double>(support("frames_in_windows")) /
          static_cast<double>(std::max<std::size_t>(1, frames.times.size())),
      fps, whole.reason);
  std::string rejected;
  for (const auto& [reason, count] : whole.rejections)
    rejected += fmt::format(" {} {}", reason, count);
  fmt::print("  rejected:{}\n", rejected.empty() ? " none" : rejected);
  std::string road_plane;  // auto and motion: what the frame pairs gave
  for (const auto& [key, count] : whole.support) {
    if (key.rfind("road_plane", 0) == 0) road_plane += fmt::format(" {} {}", key, count);
  }
  if (!road_plane.empty()) fmt::print("  road plane:{}\n", road_plane);
  if (whole.ok()) {
    fmt::print("  standard errors: roll {:.3f} pitch {:.3f} yaw {:.3f} deg\n",
               deg_from_rad(whole.roll_std.value_or(NAN)),
               deg_from_rad(whole.pitch_std.value_or(NAN)),
               deg_from_rad(whole.yaw_std.value_or(NAN)));
  }
  add_coverage_runs(drive, whole, errors, summary);
  const Diagnosis diagnosis = diagnose(whole, read_labels(drive + "/camera/labels.csv"));
  if (diagnosis.frames > 0) {
    fmt::print(
        "  over the {} frames in windows: VP error u {:+.2f} v {:+.2f} px; true road VP - forward "
        "VP v {:+.2f} px; crossfall {:+.3f} deg\n",
        diagnosis.frames, diagnosis.vp_u_error_px, diagnosis.vp_v_error_px,
        diagnosis.road_minus_forward_v_px, diagnosis.crossfall_deg);
  }
  std::vector<double> rolls, pitches, yaws;
  std::size_t begin = 0;
  while (begin < frames.times.size()) {
    std::size_t end = begin;
    while (end < frames.times.size() && frames.times[end] < frames.times[begin] + segment_s) ++end;
    // A tail shorter than half a segment is not a segment of its own.
    if (begin > 0 && frames.times[end - 1] - frames.times[begin] < 0.5 * segment_s) break;
    // A segment that is the whole drive is the result above (the calibration is deterministic):
    // not calibrated again, and not counted twice in the coverage.
    const bool whole_drive = begin == 0 && end == frames.times.size();
    const CalibrationResult part =
        whole_drive ? whole
                    : camera::calibrate_camera(slice(frames, begin, end), intrinsics, options);
    const Errors e = errors_of(part, truth);
    if (!whole_drive) {
      add_coverage_runs(
          fmt::format("{} from {:.0f} s", drive, frames.times[begin] - frames.times.front()), part,
          e, summary);
    }
    fmt::print("  segment {:.0f}-{:.0f} s: {} roll {:+.3f} pitch {:+.3f} yaw {:+.3f} deg\n",
               frames.times[begin] - frames.times.front(),
               frames.times[end - 1] - frames.times.front(), to_string(part.status), e.roll,
               e.pitch, e.yaw);
    if (part.ok()) {
      rolls.push_back(e.roll);
      pitches.push_back(e.pitch);
      yaws.push_back(e.yaw);
    }
    begin = end;
  }
  const Errors spreads{spread(rolls), spread(pitches), spread(yaws)};
  fmt::print("  spread over {} segments: roll {:.3f} pitch {:.3f} yaw {:.3f} deg\n", rolls.size(),
             spreads.roll, spreads.pitch, spreads.yaw);

  ++summary.drives;
  if (!whole.ok()) ++summary.failed;
  keep_largest(summary.worst.roll, errors.roll);
  keep_largest(summary.worst.pitch, errors.pitch);
  keep_largest(summary.worst.yaw, errors.yaw);
  keep_largest(summary.widest.roll, spreads.roll);
  keep_largest(summary.widest.pitch, spreads.pitch);
  keep_largest(summary.widest.yaw, spreads.yaw);
  summary.slowest_fps = std::min(summary.slowest_fps, fps);
  if (table.is_open()) {
    table << fmt::format(
        "{}\t{}\t{}x{}\t{}\t{}\t{:.3f}\t{:.3f}\t{:.3f}\t{:.3f}\t{:.3f}\t{:.3f}\t{:.2f}\t{:.2f}\t{:."
        "3f}\t{:.1f}\n",
        drive, ground_truth.scenario, intrinsics.width, intrinsics.height, ground_truth.seed,
        to_string(whole.status), errors.roll, errors.pitch, errors.yaw, spreads.roll, spreads.pitch,
        spreads.yaw,
        static_cast<double>(support("frames_in_windows")) /
            static_cast<double>(std::max<std::size_t>(1, frames.times.size())),
        diagnosis.vp_v_error_px, diagnosis.crossfall_deg, fps);
  }
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // As the CLI does (apps/x2car/main.cpp): image-sized buffers stay in the heap between frames, so
  // that the frames/s reported here are the CLI's (without it about 4 % fewer).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
#endif
  double segment_s = 60.0;
  camera::CameraCalibrationOptions options;
  options.keep_series = true;  // for the diagnosis against labels.csv
  std::ofstream table;
  std::vector<std::string> drives;
  bool with_ins = false;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--segment" && i + 1 < argc) {
      segment_s = std::atof(argv[++i]);
    } else if (argument == "--window-frames" && i + 1 < argc) {
      options.window_frames_at_any_rate = std::atoi(argv[++i]);  // as given, at any rate
    } else if (argument == "--ins") {
      with_ins = true;
    } else if (argument == "--estimator" && i + 1 < argc) {
      options.method = enum_from_string(camera::kCameraMethodNames, argv[++i], "--estimator");
    } else if (argument == "--table" && i + 1 < argc) {
      table.open(argv[++i], std::ios::app);
    } else {
      drives.push_back(argument);
    }
  }
  Summary summary;
  int status = 0;
  for (const std::string& drive : drives) {
    try {
      run(drive, segment_s, with_ins, options, table, summary);
    } catch (const std::exception& error) {
      fmt::print(stderr, "{}: {}\n", drive, error.what());
      status = 1;
    }
  }
  if (summary.drives > 1) {
    fmt::print(
        "summary of {} drives ({} not ok): largest |error| roll {:.3f} pitch {:.3f} yaw {:.3f} deg "
        "(target 0.2); largest segment spread roll {:.3f} (target 0.3) pitch {:.3f} yaw {:.3f} deg "
        "(target 0.1); slowest {:.1f} frames/s\n",
        summary.drives, summary.failed, summary.worst.roll, summary.worst.pitch, summary.worst.yaw,
        summary.widest.roll, summary.widest.pitch, summary.widest.yaw, summary.slowest_fps);
  }
  // Rendered drives are few: the check's 50 runs are not asked for here, the rest of it is.
  bench::CoverageCriteria criteria;
  criteria.min_runs = 1;
  for (const auto& [angle, runs] :
       {std::pair{"roll", &summary.roll_runs}, std::pair{"pitch", &summary.pitch_runs},
        std::pair{"yaw", &summary.yaw_runs}}) {
    if (runs->empty()) continue;
    const bench::CoverageSummary coverage = bench::summarise_coverage(*runs, criteria);
    fmt::print(
        "coverage of the {} standard error over {} ok results: {} within 2 SE ({:.0f} %); median "
        "|error| {:.3f}, median SE {:.3f} deg: {}\n",
        angle, coverage.runs, coverage.covered, 100.0 * coverage.fraction,
        coverage.median_abs_error, coverage.median_standard_error, coverage.verdict);
  }
  return status;
}
