#include "apps/x2car/report_output.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <utility>

#include "apps/x2car/camera_inputs.hpp"
#include "x2car/camera/camera_frames.hpp"
#include "x2car/camera/video_frames.hpp"
#include "x2car/io/image_folder.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {

std::vector<camera::FrameView> camera_frame_views(const io::DriveSensor& sensor) {
  IntrinsicsSource source;
  if (sensor.intrinsics) source.intrinsics_path = sensor.intrinsics->string();
  if (camera::is_video_file(sensor.input)) {
    return camera::sample_frame_views(camera::camera_frames_from_video(sensor.input).source,
                                      find_camera_intrinsics(sensor.input.string(), source));
  }
  const io::ImageFolder folder = io::list_images(sensor.input);
  source.camera_index = folder.kitti_camera_index;  // KITTI raw's camera X: the _0X keys
  return camera::sample_frame_views(camera::camera_frames_from(folder),
                                    find_camera_intrinsics(sensor.input.string(), source));
}

report::ReportSensor drive_report_sensor(const io::DriveSensor& sensor, CalibrationResult result,
                                         const std::optional<io::GroundTruth>& truth) {
  report::ReportSensor entry{sensor.name, std::move(result), std::nullopt, std::nullopt, {}};
  if (truth) entry.truth = io::find_mounting(*truth, sensor.name);
  if (sensor.kind == io::SensorKind::kCamera) entry.frames = camera_frame_views(sensor);
  return entry;
}

std::string path_title(const std::filesystem::path& path) {
  std::filesystem::path normal = path.lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();  // a trailing slash
  const std::string name = normal.filename().string();
  return name.empty() ? path.string() : name;
}

void write_report(const std::string& path, const report::ReportInput& input) {
  io::write_text_file(path, report::render_report_html(input));
  spdlog::info("wrote the report {}", path);
}

}  // namespace x2car::cli
