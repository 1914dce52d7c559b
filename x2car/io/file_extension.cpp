#include "x2car/io/file_extension.hpp"

#include <algorithm>
#include <cctype>

namespace x2car::io {

std::string lower_case_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::ranges::transform(extension, extension.begin(),
                         [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool is_jpeg_file(const std::filesystem::path& path) {
  const std::string extension = lower_case_extension(path);
  return extension == ".jpg" || extension == ".jpeg";
}

}  // namespace x2car::io
