#include "x2car/sim/camera_writer.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/camera_labels.hpp"
#include "x2car/sim/lidar_model.hpp"

namespace x2car::sim {
namespace {

// Days since 1970-01-01 -> (year, month, day) in the proleptic Gregorian calendar (H. Hinnant's
// civil_from_days), so that no time zone or C library clock is involved.
void civil_from_days(std::int64_t days, std::int64_t& year, unsigned& month, unsigned& day) {
  days += 719468;
  const std::int64_t era = (days >= 0 ? days : days - 146096) / 146097;
  const auto doe = static_cast<unsigned>(days - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  day = doy - (153 * mp + 2) / 5 + 1;
  month = mp < 10 ? mp + 3 : mp - 9;
  year = static_cast<std::int64_t>(yoe) + era * 400 + (month <= 2 ? 1 : 0);
}

void create_folder(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder.string(), "cannot create the folder: " + error.message());
}

}  // namespace

std::string camera_frame_file_name(std::size_t index, CameraImageFormat format) {
  return fmt::format("{:010d}{}", index, file_extension(format));
}

std::string kitti_timestamp(double start_unix_time, double offset_s) {
  const double whole = std::floor(start_unix_time);
  std::int64_t seconds = static_cast<std::int64_t>(whole);
  std::int64_t nanoseconds = std::llround((start_unix_time - whole + offset_s) * 1e9);
  seconds += nanoseconds >= 0 ? nanoseconds / 1000000000 : (nanoseconds - 999999999) / 1000000000;
  nanoseconds -=
      (nanoseconds >= 0 ? nanoseconds / 1000000000 : (nanoseconds - 999999999) / 1000000000) *
      1000000000;
  const std::int64_t days = (seconds >= 0 ? seconds : seconds - 86399) / 86400;
  const std::int64_t in_day = seconds - days * 86400;
  std::int64_t year = 0;
  unsigned month = 0, day = 0;
  civil_from_days(days, year, month, day);
  return fmt::format("{:04d}-{:02d}-{:02d} {:02d}:{:02d}:{:02d}.{:09d}", year, month, day,
                     in_day / 3600, (in_day / 60) % 60, in_day % 60, nanoseconds);
}

std::size_t write_camera_frames(const CameraRenderer& camera, const std::filesystem::path& folder,
                                double start_unix_time, const FrameProgress& progress) {
  const std::filesystem::path images = folder / "images";
  std::error_code error;
  std::filesystem::remove_all(images, error);  // no stale frames from an earlier run
  if (error) throw InputError(images.string(), "cannot empty: " + error.message());
  create_folder(images);
  const CameraImageFormat format = camera.options().format;
  const int quality = camera.options().jpeg_quality;
  std::mutex progress_mutex;
  std::size_t done = 0;
  tbb::parallel_for(std::size_t{0}, camera.frame_count(), [&](std::size_t index) {
    write_image(images / camera_frame_file_name(index, format), camera.render(index), format,
                quality);
    if (progress) {
      const std::lock_guard lock(progress_mutex);
      progress(++done, camera.frame_count());
    }
  });
  std::string text;
  for (std::size_t i = 0; i < camera.frame_count(); ++i) {
    text += kitti_timestamp(start_unix_time, camera.frame_time(i)) + "\n";
  }
  io::write_text_file(folder / "timestamps.txt", text);
  return camera.frame_count();
}

VehicleState vehicle_state_at(const VehicleStates& states, double time) {
  if (states.empty()) throw std::invalid_argument("vehicle_state_at: no states");
  auto after = std::lower_bound(states.begin(), states.end(), time,
                                [](const VehicleState& s, double t) { return s.time < t; });
  if (after == states.end() ||
      (after != states.begin() && time - (after - 1)->time < after->time - time)) {
    --after;
  }
  VehicleState state = *after;
  state.world_from_vehicle = world_from_vehicle_at(states, time);
  state.time = time;
  return state;
}

std::size_t write_simulated_camera(const World& world, const VehicleStates& states,
                                   const Eigen::Isometry3d& vehicle_from_camera,
                                   const core::CameraIntrinsics& intrinsics,
                                   const CameraOutput& output, const std::filesystem::path& folder,
                                   double start_unix_time, const FrameProgress& progress) {
  const WorldScene scene(world);
  const CameraRenderer camera(scene, states, vehicle_from_camera, intrinsics, output.options,
                              output.seed);
  const std::size_t frames = write_camera_frames(camera, folder, start_unix_time, progress);
  std::string labels = format_camera_labels_csv_header();
  for (std::size_t i = 0; i < frames; ++i) {
    labels += format_camera_label_row(
        camera_frame_label(intrinsics, vehicle_from_camera,
                           vehicle_state_at(states, camera.frame_time(i)), world.road));
  }
  io::write_text_file(folder / kCameraLabelsFile, labels);
  return frames;
}

}  // namespace x2car::sim
