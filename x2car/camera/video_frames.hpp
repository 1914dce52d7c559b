// The frames of a video file (mp4, avi, mkv, ... whatever OpenCV's videoio reads here) as the
// calibrator's frame source (issue 14 item 1; docs/formats.md, "Camera video").
//
// A video decodes in order, while the calibrator asks for frames from several threads, slightly
// out of order, and the motion estimator asks for each frame's predecessor too. So one decoder,
// behind a lock, runs ahead and keeps the last `cached_frames` frames (of those read:
// max_frame_rate_hz); a frame asked for after it left the cache is found again by reopening the
// file and decoding up to it (slow, but it happens only when the cache is smaller than the
// calibrator's frames in flight).
//
// Times: from a timestamps file (one per frame, as an image folder's timestamps.txt) when given,
// else index / frame_rate_hz when given, else each frame's presentation time in the container
// (from 0 at the first frame; a variable frame rate keeps its real times), else, when those are
// missing or not increasing, index / the container's nominal frame rate, with a note (FFmpeg
// makes one up, 25 Hz or the time base's, for a stream that gives none).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/camera_calibration.hpp"

namespace x2car::camera {

struct VideoFrameOptions {
  // One time per frame; absent: frame_rate_hz, else the container's times.
  std::optional<std::filesystem::path> timestamps;
  // Times are index / this [Hz] instead of the container's (missing or wrong there); not with
  // timestamps.
  std::optional<double> frame_rate_hz;
  // Decoded frames kept for readers behind the decoder (8-bit grey each); 0: 64, or twice the
  // calibrator's frames in flight (camera_frames_in_flight) and 16 more where that is more, so
  // that no reader falls behind the cache on a machine with many cores (each miss decodes the
  // video again from its start). Else at least 2.
  std::size_t cached_frames = 0;
  // The calibrator's CameraCalibrationOptions::max_frame_rate_hz, when it reads every n-th frame
  // only (frames_apart_for_rate): the cache then keeps those alone (as many of them), and the
  // decoder passes the others without converting them [Hz]. 0: every frame is read.
  double max_frame_rate_hz = 0.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct VideoFrames {
  CameraFrameSource source;  // 8-bit grey; keeps its own decoder state and may be copied
  // Where the times came from, for the log: "the video's frame times", "--timestamps FILE", ...
  std::string time_source;
  double mean_frame_rate_hz = 0.0;  // frames per second of the times, first to last (0: one frame)
  // The container's frame count (an estimate in some formats; 0 when it gives none).
  std::size_t container_frames = 0;
  // What the caller should tell the user: times that fell back on a nominal frame rate, a video
  // that stopped decoding well before the container's count (truncated or corrupt).
  std::vector<std::string> notes;
};

// Opens the video and counts its frames (by decoding them once: containers' frame counts are
// estimates). InputError naming the file when it cannot be opened or decoded, holds no frame, has
// no usable times (no timestamps, no frame rate, none in the container), or when the timestamps
// file's count differs from the frames'.
VideoFrames camera_frames_from_video(const std::filesystem::path& path,
                                     const VideoFrameOptions& options = {});

// The frames' times from their presentation times in the container [s], from 0 at the first, when
// they can time the frames: finite and strictly increasing, but for the frames at the end that
// read exactly 0, which the decoder held back (B-frame reordering, one per FFmpeg frame thread: as
// many as the machine's cores) and OpenCV 4.6 returns without a time; those are spaced by the
// median interval before them (`flushed`: how many). Else nullopt: a stream without presentation
// times (0 at every frame), fewer than 2 timed frames, or a time that repeats or goes back
// (re-spacing what follows would shift it).
std::optional<std::vector<double>> frame_times_from_container(
    const std::vector<double>& presentation_times_s, std::size_t& flushed);

// Whether a path names a video file by its extension (mp4, avi, mkv, mov, webm, m4v; any case).
bool is_video_file(const std::filesystem::path& path);

}  // namespace x2car::camera
