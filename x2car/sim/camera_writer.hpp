// Writing the simulated camera's frames to a drive's `camera/` folder (docs/formats.md), laid out
// as KITTI raw's image_02:
//   camera/images/NNNNNNNNNN.png   one 8-bit RGB image per frame, numbered from 0000000000
//                                  (.jpg with CameraImageFormat::kJpeg)
//   camera/timestamps.txt          one "YYYY-MM-DD HH:MM:SS.fffffffff" (UTC) per frame: the
//                                  middle of its exposure, start_unix_time + the drive's time
//   camera/labels.csv              one row of ground truth per frame (camera_labels.hpp)
// Frames are rendered and written as they are made, several in parallel, so a long drive never
// holds more than a few in memory. The bytes depend only on the simulator's arguments.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "x2car/core/camera_model.hpp"
#include "x2car/sim/camera_render.hpp"
#include "x2car/sim/vehicle_state.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim {

constexpr const char* kCameraLabelsFile = "labels.csv";

// "0000000012.png" for frame 12.
std::string camera_frame_file_name(std::size_t index, CameraImageFormat format);

// KITTI raw's time stamp of `unix_time` [s since 1970, UTC]: "2011-09-26 13:02:25.964389445".
// Nanoseconds are rounded from start + offset, kept apart so that a unix time of 1.7e9 s keeps
// its nanoseconds.
std::string kitti_timestamp(double start_unix_time, double offset_s);

// What `simulate` needs to render and write the camera's frames.
struct CameraOutput {
  CameraRenderOptions options;
  std::uint64_t seed = 0;  // of the sensor noise
};

// Frames written and the total, for a progress bar; called under a lock, `done` increasing. Must
// not throw.
using FrameProgress = std::function<void(std::size_t done, std::size_t total)>;

// Renders every frame of `camera` into `folder`/images (created, emptied first) and writes
// `folder`/timestamps.txt. Returns the number of frames. InputError when it cannot be written.
std::size_t write_camera_frames(const CameraRenderer& camera, const std::filesystem::path& folder,
                                double start_unix_time, const FrameProgress& progress = {});

// The car at `time` [s]: the state nearest in time, its pose interpolated to `time`
// (world_from_vehicle_at), for the labels of a frame.
VehicleState vehicle_state_at(const VehicleStates& states, double time);

// Builds the world's Embree scene and writes the camera at `vehicle_from_camera` (its body frame,
// camera_model.hpp) driven along `states` into `folder`: the frames (write_camera_frames) and
// their labels.
std::size_t write_simulated_camera(const World& world, const VehicleStates& states,
                                   const Eigen::Isometry3d& vehicle_from_camera,
                                   const core::CameraIntrinsics& intrinsics,
                                   const CameraOutput& output, const std::filesystem::path& folder,
                                   double start_unix_time, const FrameProgress& progress = {});

}  // namespace x2car::sim
