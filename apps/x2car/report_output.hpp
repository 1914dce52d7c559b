// What the commands that write a report (`report`, `--report` on `calibrate` and `eval`) share:
// a camera's sample frames read from its input as its command reads them, and the report file.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/frame_views.hpp"
#include "x2car/io/drive_folder.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/report/report.hpp"

namespace x2car::cli {

// A camera's sample frames (camera::sample_frame_views) from its input folder or video, with the
// intrinsics its command would find (the manifest's, or beside the images).
std::vector<camera::FrameView> camera_frame_views(const io::DriveSensor& sensor);

// The report's entry for a sensor of a drive: its result, the truth's mounting when known, a
// camera's frames.
report::ReportSensor drive_report_sensor(const io::DriveSensor& sensor, CalibrationResult result,
                                         const std::optional<io::GroundTruth>& truth);

// A path's last name for a report's title: "drive" for "runs/drive/" as for "runs/drive".
std::string path_title(const std::filesystem::path& path);

// Writes the HTML and says where (info); std::runtime_error when it cannot be written.
void write_report(const std::string& path, const report::ReportInput& input);

}  // namespace x2car::cli
