#include "x2car/camera/camera_frames.hpp"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "x2car/core/error.hpp"
#include "x2car/io/file_extension.hpp"

namespace x2car::camera {

cv::Mat read_grey_image(const std::filesystem::path& path) {
  cv::Mat image;
  try {
    image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& error) {
    throw InputError(path.string(), std::string("cannot be decoded: ") + error.what());
  }
  if (image.empty()) {
    throw InputError(path.string(),
                     "cannot be decoded as an image (missing, truncated or not a "
                     "PNG/JPEG)");
  }
  return image;
}

CameraFrameSource camera_frames_from(const io::ImageFolder& folder) {
  CameraFrameSource frames;
  frames.times.reserve(folder.images.size());
  for (const io::ImageFile& image : folder.images) frames.times.push_back(image.time);
  frames.read = [&folder](std::size_t index) { return read_grey_image(folder.images[index].path); };
  frames.name = [&folder](std::size_t index) { return folder.images[index].path.string(); };
  frames.lossy = std::ranges::any_of(
      folder.images, [](const io::ImageFile& image) { return io::is_jpeg_file(image.path); });
  return frames;
}

}  // namespace x2car::camera
