#include "x2car/sim/camera_image.hpp"

#include <array>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"

namespace x2car::sim {
namespace {

constexpr std::array<EnumName<CameraImageFormat>, 2> kFormatNames{{
    {CameraImageFormat::kPng, "png"},
    {CameraImageFormat::kJpeg, "jpg"},
}};

// zlib level of the PNGs: level 1 is several times faster than the default and ~10 % larger on
// these images.
constexpr int kPngCompression = 1;

}  // namespace

std::string to_string(CameraImageFormat format) { return enum_to_string(kFormatNames, format); }

CameraImageFormat camera_image_format_from_string(std::string_view name) {
  return enum_from_string(kFormatNames, name, "camera image format");
}

std::vector<std::string> camera_image_format_names() { return enum_names(kFormatNames); }

std::string file_extension(CameraImageFormat format) { return "." + to_string(format); }

std::vector<std::uint8_t> encode_image(const RgbImage& image, CameraImageFormat format,
                                       int jpeg_quality) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() !=
          static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3) {
    throw std::invalid_argument("encode_image: the pixels do not fit the image size");
  }
  // OpenCV keeps colour images as BGR.
  const cv::Mat rgb(image.height, image.width, CV_8UC3,
                    const_cast<std::uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  std::vector<int> parameters;
  if (format == CameraImageFormat::kPng) {
    parameters = {cv::IMWRITE_PNG_COMPRESSION, kPngCompression};
  } else {
    parameters = {cv::IMWRITE_JPEG_QUALITY, jpeg_quality};
  }
  if (!cv::imencode(file_extension(format), bgr, bytes, parameters)) {
    throw std::runtime_error("encode_image: OpenCV cannot encode " + to_string(format));
  }
  return bytes;
}

void write_image(const std::filesystem::path& path, const RgbImage& image, CameraImageFormat format,
                 int jpeg_quality) {
  const std::vector<std::uint8_t> bytes = encode_image(image, format, jpeg_quality);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) throw InputError(path.string(), "cannot write the image");
}

RgbImage read_image(const std::filesystem::path& path) {
  const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw InputError(path.string(), "cannot read an image");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  RgbImage image;
  image.width = rgb.cols;
  image.height = rgb.rows;
  image.rgb.resize(static_cast<std::size_t>(rgb.cols) * static_cast<std::size_t>(rgb.rows) * 3);
  for (int v = 0; v < rgb.rows; ++v) {
    std::copy(rgb.ptr<std::uint8_t>(v), rgb.ptr<std::uint8_t>(v) + 3 * rgb.cols,
              image.rgb.begin() + static_cast<std::ptrdiff_t>(3 * v * rgb.cols));
  }
  return image;
}

}  // namespace x2car::sim
