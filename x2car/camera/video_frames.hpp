// The frames of a video file (mp4, avi, mkv, ... whatever OpenCV's videoio reads here) as the
// calibrator's frame source (issue 14 item 1; docs/formats.md, "Camera video").
//
// A video decodes in order, while the calibrator asks for frames from several threads, slightly
// out of order, and the motion estimator asks for each frame's predecessor too. So one decoder,
// behind a lock, runs ahead and keeps the last `cached_frames` frames; a frame asked for after it
// left the cache is found again by reopening the file and decoding up to it (slow, but it happens
// only when the cache is smaller than the calibrator's frames in flight).
//
// Times: from a timestamps file (one per frame, as an image folder's timestamps.txt) when given,
// else frame index / the container's frame rate, from 0.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>

#include "x2car/camera/camera_calibration.hpp"

namespace x2car::camera {

struct VideoFrameOptions {
  // One time per frame; absent: index / frame rate.
  std::optional<std::filesystem::path> timestamps;
  // Overrides the container's frame rate [Hz] (absent or 0 there, or wrong) when no timestamps.
  std::optional<double> frame_rate_hz;
  // Decoded frames kept for readers behind the decoder (8-bit grey each).
  std::size_t cached_frames = 64;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// Opens the video and counts its frames (by decoding them once: containers' frame counts are
// estimates). InputError naming the file when it cannot be opened or decoded, holds no frame, has
// no frame rate and no timestamps, or when the timestamps file's count differs from the frames'.
// The returned source decodes as 8-bit grey; it keeps its own decoder state and may be copied.
CameraFrameSource camera_frames_from_video(const std::filesystem::path& path,
                                           const VideoFrameOptions& options = {});

// Whether a path names a video file by its extension (mp4, avi, mkv, mov, webm, m4v; any case).
bool is_video_file(const std::filesystem::path& path);

}  // namespace x2car::camera
