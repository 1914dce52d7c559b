#include "x2car/camera/camera_frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <span>
#include <string>

#include "x2car/core/error.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/jpeg_data.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera {

// The file is read once and decoded from memory, so that a JPEG cut short (io/jpeg_data.hpp),
// which the decoder would fill with grey without an error, is told from the same bytes.
cv::Mat read_grey_image(const std::filesystem::path& path) {
  const std::string bytes = io::read_text_file(path);  // binary: the bytes as they are
  const std::span<const unsigned char> data(reinterpret_cast<const unsigned char*>(bytes.data()),
                                            bytes.size());
  if (const std::optional<std::string> cut = io::jpeg_cut_short(data)) {
    throw InputError(path.string(), fmt::format("is {} (truncated or corrupt)", *cut));
  }
  cv::Mat image;  // stays empty for an empty file (imdecode asserts on one)
  if (!bytes.empty()) {
    try {
      const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8U,
                            const_cast<char*>(bytes.data()));
      image = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
    } catch (const cv::Exception& error) {
      throw InputError(path.string(), std::string("cannot be decoded: ") + error.what());
    }
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
