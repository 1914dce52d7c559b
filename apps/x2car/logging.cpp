#include "apps/x2car/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <opencv2/core/utils/logger.hpp>

namespace x2car::cli {

void configure_logging(int verbosity) {
  auto logger = spdlog::get("x2car");
  if (!logger) logger = spdlog::stderr_color_mt("x2car");
  logger->set_pattern("%^%l%$: %v");
  spdlog::level::level_enum level = spdlog::level::info;
  if (verbosity < 0) level = spdlog::level::warn;
  if (verbosity == 1) level = spdlog::level::debug;
  if (verbosity >= 2) level = spdlog::level::trace;
  logger->set_level(level);
  spdlog::set_default_logger(logger);
  // OpenCV logs to stderr on its own: videoio tries every backend on a file FFmpeg cannot open
  // (GStreamer, image sequences) and prints each one's failure, which x2car reports itself, in its
  // words and naming the file. Its messages show with -v.
  cv::utils::logging::setLogLevel(verbosity >= 1 ? cv::utils::logging::LOG_LEVEL_WARNING
                                                 : cv::utils::logging::LOG_LEVEL_SILENT);
  // FFmpeg logs through its own channel ("[mjpeg @ 0x...] overread 8" for a cut video, "moov atom
  // not found" for a file that is not one), which OpenCV sets once, from this variable, when it
  // first opens a video: quiet too, unless -v or the user's own setting.
  if (verbosity < 1) setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);
}

}  // namespace x2car::cli
