#include "apps/x2car/camera_inputs.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>

#include "x2car/camera/ins_motion.hpp"
#include "x2car/camera/opencv_intrinsics_xml.hpp"
#include "x2car/camera/video_frames.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/ins_log.hpp"
#include "x2car/io/kitti_calib_cam.hpp"

namespace x2car::cli {
namespace fs = std::filesystem;

bool is_kitti_calib(const fs::path& path) { return path.extension() == ".txt"; }

core::CameraIntrinsics read_camera_intrinsics(const fs::path& path,
                                              const IntrinsicsSource& source) {
  if (is_kitti_calib(path)) {
    // Which keys: a KITTI file holds both cameras, and a wrong guess gives a wrong model silently.
    const int index = source.camera_index.value_or(2);
    if (source.unrectified) {
      spdlog::info("intrinsics from {}: camera {:02d} unrectified (K_{:02d}, D_{:02d}, S_{:02d})",
                   path.string(), index, index, index, index);
    } else {
      spdlog::info(
          "intrinsics from {}: camera {:02d} rectified (P_rect_{:02d}, S_rect_{:02d}: KITTI's "
          "synced+rectified images; --unrectified for K_{:02d} and D_{:02d})",
          path.string(), index, index, index, index, index);
    }
    return io::read_kitti_calib_cam(
        path, source.camera_index.value_or(2),
        source.unrectified ? io::KittiImages::kUnrectified : io::KittiImages::kRectified);
  }
  spdlog::info("intrinsics from {}", path.string());
  if (camera::is_xml_file(path)) return camera::read_opencv_intrinsics_xml(path);
  return io::read_camera_info_yaml(path);
}

core::CameraIntrinsics find_camera_intrinsics(const std::string& input_path,
                                              const IntrinsicsSource& source) {
  return read_camera_intrinsics(find_intrinsics_file(input_path, source), source);
}

fs::path find_intrinsics_file(const std::string& input_path, const IntrinsicsSource& source) {
  if (!source.intrinsics_path.empty()) return source.intrinsics_path;
  const fs::path input = input_path;
  const fs::path named = input.filename().empty() ? input.parent_path() : input;
  // A video's intrinsics lie beside it.
  const fs::path folder = camera::is_video_file(input) ? input.parent_path() : input;
  for (const fs::path& candidate :
       {folder / "camera" / "intrinsics.yaml", folder / "intrinsics.yaml",
        folder / "camera" / "calib_cam_to_cam.txt", folder / "calib_cam_to_cam.txt",
        named.parent_path() / "calib_cam_to_cam.txt"}) {
    std::error_code error;
    if (fs::is_regular_file(candidate, error)) return candidate;
  }
  throw InputError(input_path, 0, "intrinsics",
                   "no camera/intrinsics.yaml or calib_cam_to_cam.txt found; give --intrinsics");
}

std::vector<std::optional<camera::VehicleMotion>> camera_motion_from_log(
    const std::string& path, const camera::CameraFrameSource& frames, const std::string& topic) {
  io::InsReadOptions read_options;
  if (!topic.empty()) read_options.topic = topic;
  const io::InsLog log = io::read_ins_log(path, read_options);
  for (const std::string& notice : log.notices) spdlog::warn("{}", notice);
  camera::InsMotionOptions options;
  const bool unix_frames = !frames.times.empty() && frames.times.front() > 1e8;
  if (unix_frames && log.start_unix_time) options.ins_to_frame_offset_s = *log.start_unix_time;
  if (!unix_frames && log.start_unix_time) {
    // Nothing ties a video's frame count (or relative times) to the log's clock: say what is
    // assumed, since a log started earlier than the video shifts every frame's motion.
    spdlog::warn(
        "{}: the frames' times are relative (they start near 0 s) but the log's are UTC; its "
        "first record is taken as the first frame's time. If the camera started at another "
        "moment, give --timestamps with the frames' UTC times",
        path);
  }
  std::vector<std::optional<camera::VehicleMotion>> motion =
      camera::motion_from_ins(frames.times, log.records, options);
  const auto covered = std::ranges::count_if(motion, [](const auto& m) { return m.has_value(); });
  spdlog::info("motion from {}: {} of {} frames covered", path, covered, motion.size());
  if (covered == 0) {
    // Say both spans: a clock mismatch shows at once (UTC frames against a log that counts from
    // 0, as a drive's ins.csv does where its novatel_enu.csv has UTC).
    std::string spans;
    if (!log.records.empty() && !frames.times.empty()) {
      spans = fmt::format(
          ": its records run {:.3f}-{:.3f} s{}, the frames {:.3f}-{:.3f} s",
          log.records.front().time, log.records.back().time,
          options.ins_to_frame_offset_s != 0.0
              ? fmt::format(" (+{:.3f} s, its UTC start)", options.ins_to_frame_offset_s)
              : "",
          frames.times.front(), frames.times.back());
    }
    std::string hint = "another clock?";
    if (unix_frames && !log.start_unix_time) {
      hint =
          "the frames' times are UTC, the log's count from its own start and it gives no UTC "
          "start: give a log with UTC times, or --timestamps with the frames on the log's clock";
    }
    throw InputError(path, 0, "time",
                     fmt::format("the log covers none of the frames' times{} ({})", spans, hint));
  }
  if (static_cast<std::size_t>(covered) < motion.size()) {
    spdlog::warn(
        "{}: the log covers only {} of the {} frames; the others are gated and calibrated "
        "without the car's motion",
        path, covered, motion.size());
  }
  return motion;
}

}  // namespace x2car::cli
