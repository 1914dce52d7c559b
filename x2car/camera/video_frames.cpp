#include "x2car/camera/video_frames.hpp"

#include <fmt/format.h>

#include <cmath>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <system_error>
#include <utility>

#include "x2car/camera/grey_image.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/timestamps_file.hpp"

namespace x2car::camera {

void VideoFrameOptions::Check() const {
  const OptionsCheck check("VideoFrameOptions");
  if (frame_rate_hz) check.positive("frame_rate_hz", *frame_rate_hz);
  check.at_least("cached_frames", static_cast<double>(cached_frames), 2.0);
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

// The one decoder of a source, shared by its copies and its reader threads.
class SequentialDecoder {
 public:
  SequentialDecoder(std::filesystem::path path, std::size_t frame_count, std::size_t cached)
      : path_(std::move(path)), frame_count_(frame_count), cached_(cached) {}

  cv::Mat frame(std::size_t index) {
    const std::lock_guard lock(mutex_);
    if (index >= frame_count_) {
      throw InputError(path_.string(), fmt::format("has no frame {}", index));
    }
    if (index < first_cached()) reopen();  // behind the cache: start again
    while (next_ <= index) decode_next();
    return cache_[index - first_cached()].clone();
  }

 private:
  std::size_t first_cached() const { return next_ - cache_.size(); }

  void reopen() {
    capture_ = open_video(path_);
    cache_.clear();
    next_ = 0;
  }

  void decode_next() {
    if (!capture_.isOpened()) capture_ = open_video(path_);
    cv::Mat image;
    if (!capture_.read(image) || image.empty()) {
      throw InputError(path_.string(), fmt::format("frame {} cannot be decoded", next_));
    }
    cache_.push_back(grey_8bit(image).clone());
    if (cache_.size() > cached_) cache_.pop_front();
    ++next_;
  }

  std::filesystem::path path_;
  std::size_t frame_count_;
  std::size_t cached_;
  std::mutex mutex_;
  cv::VideoCapture capture_;
  std::deque<cv::Mat> cache_;  // frames next_ - size .. next_ - 1
  std::size_t next_ = 0;       // the index the decoder reads next
};

// Decodes the whole video once to count its frames and check that each decodes.
std::size_t count_frames(const std::filesystem::path& path, double& frame_rate_hz) {
  cv::VideoCapture capture = open_video(path);
  frame_rate_hz = capture.get(cv::CAP_PROP_FPS);
  std::size_t count = 0;
  while (capture.grab()) ++count;
  if (count == 0) throw InputError(path.string(), "holds no frame that can be decoded");
  return count;
}

}  // namespace

CameraFrameSource camera_frames_from_video(const std::filesystem::path& path,
                                           const VideoFrameOptions& options) {
  options.Check();
  double container_rate_hz = 0.0;
  const std::size_t count = count_frames(path, container_rate_hz);
  CameraFrameSource frames;
  if (options.timestamps) {
    frames.times = io::read_timestamps_file(*options.timestamps);
    if (frames.times.size() != count) {
      throw InputError(options.timestamps->string(),
                       fmt::format("holds {} timestamps but {} has {} frames", frames.times.size(),
                                   path.string(), count));
    }
  } else {
    const double rate_hz = options.frame_rate_hz.value_or(container_rate_hz);
    if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
      throw InputError(path.string(), 0, "frame rate",
                       "the video gives no frame rate; give one or a timestamps file");
    }
    frames.times.reserve(count);
    for (std::size_t i = 0; i < count; ++i)
      frames.times.push_back(static_cast<double>(i) / rate_hz);
  }
  auto decoder = std::make_shared<SequentialDecoder>(path, count, options.cached_frames);
  frames.read = [decoder](std::size_t index) { return decoder->frame(index); };
  // Cameras' videos are coded with loss (H.264, H.265, MJPEG); a lossless one (FFV1) is taken as
  // lossy too, which costs it little (CameraCalibrationOptions::lossy_tracking_window_px).
  frames.lossy = true;
  frames.name = [name = path.string()](std::size_t index) {
    return fmt::format("{} frame {}", name, index);
  };
  return frames;
}

}  // namespace x2car::camera
