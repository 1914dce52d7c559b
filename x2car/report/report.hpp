// x2car's report (issue 16 item 3-4): one self-contained HTML file that opens offline, with for
// each sensor its result card, the evidence behind the estimate as interactive charts (the
// paper's Figs. 7-9: heading curves, per-segment estimates, the radar's Doppler cosine), the
// error against the truth when known, and for a camera its frames with the lines, vanishing point
// and horizon, plus a view whose roll/pitch/yaw sliders move the projected horizon and lane guides
// and export the adjusted mounting.
//
// The page is the data (report_data_json, embedded as JSON) drawn by the report's own script
// (web/report.js) with Apache ECharts, both inlined at build time from the pinned npm packages
// (web/package-lock.json): no network at view time.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/frame_views.hpp"
#include "x2car/core/calibration_result.hpp"
#include "x2car/eval/eval_json.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/result_json.hpp"

namespace x2car::report {

struct ReportSensor {
  std::string name;                         // the sensor's frame, e.g. "lidar_roof"
  CalibrationResult result;                 // the whole log's, with its series when it kept them
  std::optional<io::SensorMounting> truth;  // its vehicle_from_sensor, when known
  std::optional<eval::SensorEvaluation> evaluation;  // `x2car eval`'s segments
  std::vector<camera::FrameView> frames;             // a camera's sample frames
};

struct ReportInput {
  std::string title;    // e.g. the drive folder's name
  std::string command;  // the command line that made it, shown in the page's footer
  std::vector<ReportSensor> sensors;
};

struct ReportOptions {
  // Each series is cut to at most this many samples (series_decimation.hpp): a 30-minute log's
  // report stays a few megabytes and draws at once.
  std::size_t max_points_per_series = 3000;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// What the page draws: {"title", "command", "sensors": [{"name", "result", "truth",
// "evaluation", "frames"}]} with angles in degrees as in the result JSON, series decimated and
// rounded to what a plot resolves, and frames as base64 JPEG with their pinhole K, lines,
// vanishing point and horizon.
io::Json report_data_json(const ReportInput& input, const ReportOptions& options = {});

// The HTML document: the data, the chart library, the report's script and style in one file.
std::string render_report_html(const ReportInput& input, const ReportOptions& options = {});

}  // namespace x2car::report
