#include "x2car/report/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string_view>

#include "x2car/core/options_check.hpp"
#include "x2car/report/report_assets.hpp"
#include "x2car/report/series_decimation.hpp"

namespace x2car::report {

void ReportOptions::Check() const {
  const OptionsCheck check("ReportOptions");
  check.at_least("max_points_per_series", static_cast<double>(max_points_per_series), 2.0);
}

namespace {

// Rounded to `digits` significant digits: a plot resolves a few thousand steps, and full doubles
// would triple the page's size.
double rounded(double value, int digits) {
  if (!std::isfinite(value) || value == 0.0) return value;
  const double magnitude = std::pow(10.0, digits - 1 - std::floor(std::log10(std::abs(value))));
  return std::round(value * magnitude) / magnitude;
}

io::Json number_or_null(double value) { return std::isfinite(value) ? io::Json(value) : nullptr; }

// Series the page draws against each other (a map, the radar's Fig. 9): thinned at one stride so
// their samples stay paired; the rest are drawn against time and keep their peaks.
bool drawn_as_pairs(const std::string& name) {
  return name.starts_with("odometry_") || name.starts_with("doppler_");
}

// The series, decimated; times kept to the millisecond, values to 6 significant digits.
io::Json series_json(const std::vector<Series>& all, std::size_t max_points) {
  io::Json list = io::Json::array();
  for (const Series& full : all) {
    const Series series = drawn_as_pairs(full.name) ? thin_series(full, max_points)
                                                    : decimate_series(full, max_points);
    io::Json time = io::Json::array();
    io::Json value = io::Json::array();
    for (const double t : series.time) time.push_back(number_or_null(std::round(t * 1e3) / 1e3));
    for (const double v : series.value) value.push_back(number_or_null(rounded(v, 6)));
    list.push_back(
        {{"name", series.name}, {"unit", series.unit}, {"time", time}, {"value", value}});
  }
  return list;
}

io::Json result_json(const CalibrationResult& result, std::size_t max_points) {
  io::Json json = io::result_to_json(result, {.include_series = false, .include_timing = true});
  json["series"] = series_json(result.series, max_points);
  return json;
}

io::Json truth_json(const io::SensorMounting& truth) {
  return {{"roll_deg", deg_from_rad(truth.rotation.roll)},
          {"pitch_deg", deg_from_rad(truth.rotation.pitch)},
          {"yaw_deg", deg_from_rad(truth.rotation.yaw)},
          {"x_m", truth.translation.x()},
          {"y_m", truth.translation.y()},
          {"z_m", truth.translation.z()}};
}

std::string base64(std::string_view bytes) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t left = bytes.size() - i;
    std::uint32_t group = static_cast<unsigned char>(bytes[i]) << 16;
    if (left > 1) group |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (left > 2) group |= static_cast<unsigned char>(bytes[i + 2]);
    text += kAlphabet[(group >> 18) & 63];
    text += kAlphabet[(group >> 12) & 63];
    text += left > 1 ? kAlphabet[(group >> 6) & 63] : '=';
    text += left > 2 ? kAlphabet[group & 63] : '=';
  }
  return text;
}

const char* role_name(camera::LineRole role) {
  switch (role) {
    case camera::LineRole::kRoad:
      return "road";
    case camera::LineRole::kHorizon:
      return "horizon";
    case camera::LineRole::kOther:
      break;
  }
  return "other";
}

io::Json frame_json(const camera::FrameView& view) {
  const core::CameraIntrinsics& k = view.intrinsics;
  io::Json lines = io::Json::array();
  for (const camera::FrameLine& line : view.lines) {
    lines.push_back({rounded(line.start_px.x(), 5), rounded(line.start_px.y(), 5),
                     rounded(line.end_px.x(), 5), rounded(line.end_px.y(), 5),
                     role_name(line.role)});
  }
  const camera::FrameEstimate& estimate = view.estimate;
  io::Json json = {{"name", view.name},
                   {"time_s", view.time_s},
                   {"width", k.width},
                   {"height", k.height},
                   {"fx", k.fx},
                   {"fy", k.fy},
                   {"cx", k.cx},
                   {"cy", k.cy},
                   {"jpeg_base64", base64(view.jpeg)},
                   {"lines", lines},
                   {"rejection", estimate.rejection ? camera::to_string(*estimate.rejection) : ""},
                   {"vanishing_point", nullptr},
                   {"horizon", nullptr}};
  if (estimate.usable()) {
    json["vanishing_point"] = {estimate.road_vanishing_point_px.x(),
                               estimate.road_vanishing_point_px.y()};
    json["horizon"] = {estimate.horizon_line.x(), estimate.horizon_line.y(),
                       estimate.horizon_line.z()};
  }
  return json;
}

// Text inside <script>: "</" would end the element early (HTML's script data rules).
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) {
    text.replace(at, 2, "<\\/");
  }
  return text;
}

std::string html_escaped(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

}  // namespace

io::Json report_data_json(const ReportInput& input, const ReportOptions& options) {
  options.Check();
  io::Json sensors = io::Json::array();
  for (const ReportSensor& sensor : input.sensors) {
    io::Json entry = {{"name", sensor.name},
                      {"result", result_json(sensor.result, options.max_points_per_series)},
                      {"truth", nullptr},
                      {"evaluation", nullptr},
                      {"frames", io::Json::array()}};
    if (sensor.truth) entry["truth"] = truth_json(*sensor.truth);
    if (sensor.evaluation) {
      entry["evaluation"] = eval::evaluation_to_json(
          *sensor.evaluation, {.include_series = false, .include_timing = true});
    }
    for (const camera::FrameView& view : sensor.frames) entry["frames"].push_back(frame_json(view));
    sensors.push_back(std::move(entry));
  }
  return {{"title", input.title}, {"command", input.command}, {"sensors", sensors}};
}

std::string render_report_html(const ReportInput& input, const ReportOptions& options) {
  const std::string data =
      report_data_json(input, options).dump(-1, ' ', false, io::Json::error_handler_t::replace);
  std::string html;
  html.reserve(data.size() + 1'500'000);
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += fmt::format("<title>x2car report: {}</title>\n", html_escaped(input.title));
  html += "<style>\n" + report_css() + "\n</style>\n</head>\n<body>\n";
  html += "<noscript>This report draws its charts with JavaScript; please enable it.</noscript>\n";
  html += "<div id=\"x2car-report\"></div>\n";
  html +=
      "<script type=\"application/json\" id=\"x2car-data\">" + script_safe(data) + "</script>\n";
  html += "<script>\n" + script_safe(echarts_js()) + "\n</script>\n";
  html += "<script>\n" + script_safe(report_js()) + "\n</script>\n";
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace x2car::report
