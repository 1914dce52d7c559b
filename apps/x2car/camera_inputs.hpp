// What `calibrate camera` and `eval` both need to read a camera log: its intrinsics, found as the
// user gave them or beside the images, and the car's motion at each frame from a GNSS/INS log.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/core/camera_model.hpp"

namespace x2car::cli {

struct IntrinsicsSource {
  std::string intrinsics_path;      // --intrinsics; empty: looked for beside the input
  std::optional<int> camera_index;  // KITTI's camera (calib_cam_to_cam.txt), default 2
  bool unrectified = false;         // KITTI's unrectified images: K_0X and D_0X
};

// The intrinsics file: --intrinsics, else the drive's camera/intrinsics.yaml, else a KITTI
// calib_cam_to_cam.txt in the input folder or the folder above it (KITTI raw keeps it beside the
// drives of a day); a video's beside the video. InputError naming the input when none is found.
std::filesystem::path find_intrinsics_file(const std::string& input_path,
                                           const IntrinsicsSource& source);

// Whether `path` is read as a KITTI calib_cam_to_cam.txt (by its extension, .txt).
bool is_kitti_calib(const std::filesystem::path& path);

// The intrinsics in `path` (a ROS camera_info or OpenCV YAML, an OpenCV FileStorage .xml, or a
// KITTI calib_cam_to_cam.txt, whose keys of camera source.camera_index, default 2, are read).
core::CameraIntrinsics read_camera_intrinsics(const std::filesystem::path& path,
                                              const IntrinsicsSource& source);

// read_camera_intrinsics(find_intrinsics_file(...)).
core::CameraIntrinsics find_camera_intrinsics(const std::string& input_path,
                                              const IntrinsicsSource& source);

// The car's speed and yaw rate at each frame from a GNSS/INS log. Frames stamped in Unix time
// (KITTI raw, the simulator) meet a log with absolute times on the Unix clock; otherwise both are
// taken to share one clock. InputError naming the log when it covers none of the frames.
// `topic`: a bag's pose topic (empty: its only one).
std::vector<std::optional<camera::VehicleMotion>> camera_motion_from_log(
    const std::string& path, const camera::CameraFrameSource& frames,
    const std::string& topic = {});

}  // namespace x2car::cli
