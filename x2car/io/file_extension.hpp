// A file's kind by its name's extension, whatever its case (folders of images, sweeps, videos).
#pragma once

#include <filesystem>
#include <string>

namespace x2car::io {

// The extension with its dot, in lower case: ".png" of "frame.PNG", "" of "README".
std::string lower_case_extension(const std::filesystem::path& path);

// Whether the file is a JPEG image by its name (.jpg, .jpeg, any case): coded with loss.
bool is_jpeg_file(const std::filesystem::path& path);

}  // namespace x2car::io
