#include "x2car/camera/video_frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "x2car/camera/grey_image.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/timestamps_file.hpp"

namespace x2car::camera {

void VideoFrameOptions::Check() const {
  const OptionsCheck check("VideoFrameOptions");
  if (frame_rate_hz) check.positive("frame_rate_hz", *frame_rate_hz);
  check.that(!(frame_rate_hz && timestamps), "frame_rate_hz",
             "and timestamps both give the times; give one");
  if (cached_frames != 0) {
    check.at_least("cached_frames", static_cast<double>(cached_frames), 2.0);
  }
  check.non_negative("max_frame_rate_hz", max_frame_rate_hz);
}

bool is_video_file(const std::filesystem::path& path) {
  const std::string extension = io::lower_case_extension(path);
  return extension == ".mp4" || extension == ".avi" || extension == ".mkv" || extension == ".mov" ||
         extension == ".webm" || extension == ".m4v";
}

namespace {

cv::VideoCapture open_video(const std::filesystem::path& path) {
  std::error_code error_code;
  if (!std::filesystem::is_regular_file(path, error_code)) {
    throw InputError(path.string(), "does not exist or is not a file");
  }
  cv::VideoCapture capture;
  try {
    // The absolute path: FFmpeg reads a relative name with a colon ("2024-05-01T10:00:00.mp4")
    // as a URL whose scheme is the part before it.
    capture.open(std::filesystem::absolute(path, error_code).string(), cv::CAP_ANY);
  } catch (const cv::Exception& error) {
    throw InputError(path.string(), std::string("cannot be opened as a video: ") + error.what());
  }
  if (!capture.isOpened()) {
    throw InputError(path.string(),
                     "cannot be opened as a video (missing, or a format this OpenCV cannot read)");
  }
  return capture;
}

// The one decoder of a source, shared by its copies and its reader threads. It keeps the last
// `cached` frames it decoded of those a reader will ask for (every `stride`-th, the calibrator's
// frames_apart_for_rate, and any frame asked for); the others it decodes without converting them
// and lets go, so that the cache spans as many of the frames read at any stride.
class SequentialDecoder {
 public:
  SequentialDecoder(std::filesystem::path path, std::size_t frame_count, std::size_t cached,
                    std::size_t stride)
      : path_(std::move(path)), frame_count_(frame_count), cached_(cached), stride_(stride) {}

  cv::Mat frame(std::size_t index) {
    const std::lock_guard lock(mutex_);
    if (index >= frame_count_) {
      throw InputError(path_.string(), fmt::format("has no frame {}", index));
    }
    if (index < next_) {
      for (auto kept = cache_.rbegin(); kept != cache_.rend(); ++kept) {
        if (kept->first == index) return kept->second.clone();
      }
      reopen();  // behind the cache, or a frame let go: start again
    }
    while (next_ < index) decode_next(false);
    decode_next(true);
    return cache_.back().second.clone();
  }

 private:
  void reopen() {
    capture_ = open_video(path_);
    cache_.clear();
    next_ = 0;
  }

  // Decodes frame next_; keeps it when `wanted` or on the stride.
  void decode_next(bool wanted) {
    if (!capture_.isOpened()) capture_ = open_video(path_);
    if (wanted || next_ % stride_ == 0) {
      cv::Mat image;
      if (!capture_.read(image) || image.empty()) {
        throw InputError(path_.string(), fmt::format("frame {} cannot be decoded", next_));
      }
      cache_.emplace_back(next_, grey_8bit(image).clone());
      if (cache_.size() > cached_) cache_.pop_front();
    } else if (!capture_.grab()) {
      throw InputError(path_.string(), fmt::format("frame {} cannot be decoded", next_));
    }
    ++next_;
  }

  std::filesystem::path path_;
  std::size_t frame_count_;
  std::size_t cached_;
  std::size_t stride_;
  std::mutex mutex_;
  cv::VideoCapture capture_;
  std::deque<std::pair<std::size_t, cv::Mat>> cache_;  // (index, frame), in decoding order
  std::size_t next_ = 0;                               // the index the decoder reads next
};

// What one pass of decoding found.
struct VideoScan {
  std::vector<double> times_s;       // each frame's presentation time, from its container
  double nominal_rate_hz = 0.0;      // the container's frame rate (FFmpeg makes one up if none)
  std::size_t container_frames = 0;  // the container's count (0: none)

  std::size_t frames() const { return times_s.size(); }  // decoded
};

// Decodes the whole video once to count its frames, check that each decodes and read its times.
VideoScan scan_video(const std::filesystem::path& path) {
  cv::VideoCapture capture = open_video(path);
  VideoScan scan;
  scan.nominal_rate_hz = capture.get(cv::CAP_PROP_FPS);
  const double container_frames = capture.get(cv::CAP_PROP_FRAME_COUNT);
  if (std::isfinite(container_frames) && container_frames > 0.0 && container_frames < 1e9) {
    scan.container_frames = static_cast<std::size_t>(std::llround(container_frames));
  }
  while (capture.grab()) {
    scan.times_s.push_back(1e-3 * capture.get(cv::CAP_PROP_POS_MSEC));
  }
  if (scan.frames() == 0) throw InputError(path.string(), "holds no frame that can be decoded");
  return scan;
}

}  // namespace

std::optional<std::vector<double>> frame_times_from_container(const std::vector<double>& times_s,
                                                              std::size_t& flushed) {
  std::size_t timed = times_s.size();
  while (timed > 0 && times_s[timed - 1] == 0.0) --timed;
  flushed = times_s.size() - timed;
  if (timed < 2) return std::nullopt;
  for (std::size_t i = 0; i < timed; ++i) {
    if (!std::isfinite(times_s[i]) || (i > 0 && !(times_s[i] > times_s[i - 1]))) {
      return std::nullopt;
    }
  }
  std::vector<double> times(times_s.begin(), times_s.begin() + static_cast<std::ptrdiff_t>(timed));
  for (double& time : times) time -= times_s.front();
  if (flushed > 0) {
    std::vector<double> intervals;
    intervals.reserve(times.size() - 1);
    for (std::size_t i = 1; i < times.size(); ++i) intervals.push_back(times[i] - times[i - 1]);
    const double median_interval_s = median(intervals);
    while (times.size() < times_s.size()) times.push_back(times.back() + median_interval_s);
  }
  return times;
}

namespace {

std::vector<double> times_from_rate(std::size_t count, double rate_hz) {
  std::vector<double> times;
  times.reserve(count);
  for (std::size_t i = 0; i < count; ++i) times.push_back(static_cast<double>(i) / rate_hz);
  return times;
}

// Frame rates a camera's video can have [Hz]: FFmpeg gives the time base's rate (90 kHz, 1 kHz)
// for a stream without one.
constexpr double kMaxPlausibleFrameRateHz = 500.0;

}  // namespace

VideoFrames camera_frames_from_video(const std::filesystem::path& path,
                                     const VideoFrameOptions& options) {
  options.Check();
  const VideoScan scan = scan_video(path);
  VideoFrames video;
  video.container_frames = scan.container_frames;
  CameraFrameSource& frames = video.source;
  if (options.timestamps) {
    frames.times = io::read_timestamps_file(*options.timestamps);
    if (frames.times.size() != scan.frames()) {
      throw InputError(options.timestamps->string(),
                       fmt::format("holds {} timestamps but {} has {} frames{}",
                                   frames.times.size(), path.string(), scan.frames(),
                                   scan.container_frames > scan.frames()
                                       ? fmt::format(" (its container lists {}: truncated?)",
                                                     scan.container_frames)
                                       : std::string()));
    }
    video.time_source = fmt::format("the timestamps file {}", options.timestamps->string());
  } else if (options.frame_rate_hz) {
    frames.times = times_from_rate(scan.frames(), *options.frame_rate_hz);
    video.time_source = fmt::format("the frame rate given, {:g} Hz", *options.frame_rate_hz);
  } else if (std::size_t flushed = 0; std::optional<std::vector<double>> times =
                                          frame_times_from_container(scan.times_s, flushed)) {
    // From 0 at the first frame, as the other sources without a timestamps file.
    frames.times = std::move(*times);
    video.time_source = flushed == 0
                            ? std::string("the video's frame times")
                            : fmt::format(
                                  "the video's frame times (the last {}, which the decoder gives "
                                  "without one, a median interval apart)",
                                  flushed);
  } else {
    const double rate_hz = scan.nominal_rate_hz;
    if (scan.frames() > 1 &&
        (!(rate_hz > 0.0) || !std::isfinite(rate_hz) || rate_hz > kMaxPlausibleFrameRateHz)) {
      throw InputError(path.string(), 0, "frame rate",
                       fmt::format("the video gives no frame times and no plausible frame rate "
                                   "({:g} Hz); give --frame-rate or a timestamps file",
                                   rate_hz));
    }
    frames.times = times_from_rate(scan.frames(), rate_hz > 0.0 ? rate_hz : 1.0);
    video.time_source = fmt::format("the video's nominal frame rate, {:g} Hz", rate_hz);
    if (scan.frames() > 1) {
      video.notes.push_back(fmt::format(
          "{}: the frames carry no increasing times; they are timed by the container's nominal "
          "frame rate, {:g} Hz (FFmpeg makes one up for a stream that has none); give "
          "--frame-rate or a timestamps file if that is not the camera's",
          path.string(), rate_hz));
    }
  }
  if (scan.frames() == 1 && scan.container_frames <= 1) {
    video.notes.push_back(fmt::format(
        "{}: holds a single frame (an image with a video's name?); calibrating needs a drive",
        path.string()));
  }
  if (frames.times.size() > 1) {
    video.mean_frame_rate_hz =
        static_cast<double>(frames.times.size() - 1) / (frames.times.back() - frames.times.front());
  }
  // A container's count is an estimate in some formats (a frame or so off; Matroska's is its
  // duration times the nominal rate, which for a variable rate is the time base's): trusted only
  // when the nominal rate is the frames' own, and then one well above the frames decoded means
  // decoding stopped early.
  const bool nominal_rate_holds =
      scan.nominal_rate_hz > 0.0 && scan.nominal_rate_hz <= kMaxPlausibleFrameRateHz &&
      (scan.frames() < 3 ||
       std::abs(scan.nominal_rate_hz - video.mean_frame_rate_hz) <= 0.05 * scan.nominal_rate_hz);
  if (nominal_rate_holds &&
      scan.container_frames >
          scan.frames() + std::max<std::size_t>(2, scan.container_frames / 50)) {
    video.notes.push_back(fmt::format(
        "{}: decoding stopped after {} of the {} frames the container lists (the file "
        "is truncated or corrupt from frame {} on); calibrating those {}",
        path.string(), scan.frames(), scan.container_frames, scan.frames(), scan.frames()));
  }
  const std::size_t cached = options.cached_frames != 0
                                 ? options.cached_frames
                                 : std::max<std::size_t>(64, 2 * camera_frames_in_flight() + 16);
  auto decoder = std::make_shared<SequentialDecoder>(
      path, scan.frames(), cached, frames_apart_for_rate(frames.times, options.max_frame_rate_hz));
  frames.read = [decoder](std::size_t index) { return decoder->frame(index); };
  // Cameras' videos are coded with loss (H.264, H.265, MJPEG); a lossless one (FFV1) is taken as
  // lossy too, which costs it little (CameraCalibrationOptions::lossy_tracking_window_px).
  frames.lossy = true;
  frames.name = [name = path.string()](std::size_t index) {
    return fmt::format("{} frame {}", name, index);
  };
  return video;
}

}  // namespace x2car::camera
