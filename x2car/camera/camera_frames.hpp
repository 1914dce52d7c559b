// The frames of an image folder (io/image_folder.hpp) as the calibrator's frame source: decoded
// with OpenCV's imgcodecs (PNG, JPEG), as 8-bit grey, the only channel the estimators use.
#pragma once

#include <opencv2/core.hpp>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/io/image_folder.hpp"

namespace x2car::camera {

// Decodes one image as 8-bit grey; InputError naming the file when it is missing or cannot be
// decoded (truncated, not an image), and when it is a JPEG cut short (io/jpeg_data.hpp), which
// the decoder would fill with grey.
cv::Mat read_grey_image(const std::filesystem::path& path);

// Times and a reader over the folder's images (the folder must outlive the source).
CameraFrameSource camera_frames_from(const io::ImageFolder& folder);

}  // namespace x2car::camera
