#include "x2car/camera/camera_frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/jpeg_data.hpp"

namespace x2car::camera {

namespace {

// InputError when the file is a JPEG cut short (io/jpeg_data.hpp): the decoder would fill its
// missing rows with grey and raise no error.
void check_jpeg_whole(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  unsigned char start[2] = {0, 0};
  if (!stream.read(reinterpret_cast<char*>(start), 2) || !io::starts_as_jpeg(start)) return;
  stream.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(std::max<std::streamoff>(0, stream.tellg()));
  std::vector<unsigned char> bytes(size);
  stream.seekg(0);
  if (!stream.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    throw InputError(path.string(), "read error");
  }
  if (const std::optional<std::size_t> offset = io::jpeg_break_offset(bytes)) {
    throw InputError(path.string(), fmt::format("is {} (truncated or corrupt)",
                                                io::describe_jpeg_break(*offset, size)));
  }
}

}  // namespace

cv::Mat read_grey_image(const std::filesystem::path& path) {
  check_jpeg_whole(path);
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
