// A rendered camera image and its files: 8-bit RGB, written as PNG (lossless, the default) or JPEG
// through OpenCV's imgcodecs. The bytes depend only on the pixels and the options: PNG at a fixed
// compression level, no time stamps or other metadata.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace x2car::sim {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // row by row, 3 bytes a pixel (R, G, B)

  std::uint8_t at(int u, int v, int channel) const {
    return rgb[(static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                static_cast<std::size_t>(u)) *
                   3 +
               static_cast<std::size_t>(channel)];
  }
};

enum class CameraImageFormat { kPng, kJpeg };

std::string to_string(CameraImageFormat format);  // "png", "jpg"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
CameraImageFormat camera_image_format_from_string(std::string_view name);
std::vector<std::string> camera_image_format_names();  // the CLI's choices
std::string file_extension(CameraImageFormat format);  // ".png", ".jpg"

// The encoded file. `jpeg_quality` 1..100 (JPEG only). Throws std::runtime_error when OpenCV
// cannot encode it.
std::vector<std::uint8_t> encode_image(const RgbImage& image, CameraImageFormat format,
                                       int jpeg_quality = 92);
// Writes it; InputError naming the file when it cannot be written.
void write_image(const std::filesystem::path& path, const RgbImage& image, CameraImageFormat format,
                 int jpeg_quality = 92);
// Reads an 8-bit colour image (tests, tools); InputError naming the file when it cannot be read.
RgbImage read_image(const std::filesystem::path& path);

}  // namespace x2car::sim
