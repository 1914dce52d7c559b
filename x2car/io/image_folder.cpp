#include "x2car/io/image_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <string_view>
#include <system_error>

#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/file_stem_time.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/timestamps_file.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;

bool folder_exists(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

bool file_exists(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

bool is_image(const fs::path& path) {
  const std::string extension = lower_case_extension(path);
  return extension == ".png" || is_jpeg_file(path);
}

// Hidden files (".name"): macOS writes a "._name" companion beside every file copied to a foreign
// disk, with the image's extension and no image in it.
bool is_hidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name.front() == '.';
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Name order with runs of digits compared as numbers: "frame_2.png" before "frame_10.png". Equal
// numbers written with different zeros ("07", "7") are told apart by the names' plain order, so
// that the order is total.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      std::size_t a_end = i, b_end = j;
      while (a_end < a.size() && is_digit(a[a_end])) ++a_end;
      while (b_end < b.size() && is_digit(b[b_end])) ++b_end;
      std::size_t a_start = i, b_start = j;
      while (a_start + 1 < a_end && a[a_start] == '0') ++a_start;  // leading zeros
      while (b_start + 1 < b_end && b[b_start] == '0') ++b_start;
      const std::string_view a_number(a.data() + a_start, a_end - a_start);
      const std::string_view b_number(b.data() + b_start, b_end - b_start);
      if (a_number.size() != b_number.size()) return a_number.size() < b_number.size();
      if (a_number != b_number) return a_number < b_number;
      i = a_end;
      j = b_end;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  if (i < a.size() || j < b.size()) return j < b.size() && i == a.size();
  return a < b;
}

// Image files directly in `folder`, in natural name order; the other files counted.
std::vector<fs::path> image_files(const fs::path& folder, std::size_t& others) {
  std::vector<fs::path> images;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (!entry.is_regular_file()) continue;
    if (is_image(entry.path()) && !is_hidden(entry.path())) {
      images.push_back(entry.path());
    } else {
      ++others;
    }
  }
  if (error) throw InputError(folder.string(), "cannot list the folder: " + error.message());
  std::ranges::sort(images, [](const fs::path& a, const fs::path& b) {
    return natural_less(a.filename().string(), b.filename().string());
  });
  return images;
}

// The images of `images_folder` with the times of `timestamps` (one per image, name order) or,
// without one, of their names.
ImageFolder list_with_times(const fs::path& images_folder,
                            const std::optional<fs::path>& timestamps) {
  ImageFolder result;
  result.folder = images_folder;
  const std::vector<fs::path> files = image_files(images_folder, result.ignored_files);
  if (files.empty()) {
    throw InputError(images_folder.string(), "holds no images (*.png, *.jpg, *.jpeg)");
  }
  if (timestamps) {
    const std::vector<double> times = read_timestamps_file(*timestamps);
    if (times.size() != files.size()) {
      // Name where the two lists part, so that a stray or missing file is found at once.
      const std::string where =
          times.size() < files.size()
              ? fmt::format("the first image without a time is {} (image {} in name order)",
                            files[times.size()].filename().string(), times.size() + 1)
              : fmt::format("timestamps {} on have no image (the last image is {})",
                            files.size() + 1, files.back().filename().string());
      throw InputError(timestamps->string(),
                       fmt::format("holds {} timestamps but {} has {} images: {}", times.size(),
                                   images_folder.string(), files.size(), where));
    }
    for (std::size_t i = 0; i < files.size(); ++i) result.images.push_back({files[i], times[i]});
    result.time_source = timestamps->string();
    result.timestamps_file = *timestamps;
    return result;
  }
  for (const fs::path& file : files) {
    const std::optional<double> time = time_from_file_stem(file.stem().string());
    if (!time) {
      throw InputError(file.string(), 0, "file name",
                       "no timestamps.txt beside the images and the name is not a time (seconds "
                       "with a fraction, or 16+ digits of nanoseconds)");
    }
    result.images.push_back({file, *time});
  }
  std::ranges::stable_sort(result.images, {}, &ImageFile::time);
  for (std::size_t i = 1; i < result.images.size(); ++i) {
    if (result.images[i].time == result.images[i - 1].time) {
      throw InputError(
          result.images[i].path.string(), 0, "file name",
          fmt::format("has the same time as {}", result.images[i - 1].path.filename().string()));
    }
  }
  result.time_source = "file names";
  return result;
}

std::optional<fs::path> existing_file(const fs::path& path) {
  return file_exists(path) ? std::optional<fs::path>(path) : std::nullopt;
}

// A camera folder: images/ or data/ with timestamps.txt beside them.
std::optional<ImageFolder> list_camera_folder(const fs::path& folder) {
  for (const char* images : {"images", "data"}) {
    if (folder_exists(folder / images)) {
      return list_with_times(folder / images, existing_file(folder / "timestamps.txt"));
    }
  }
  return std::nullopt;
}

// The X of a KITTI camera folder's name, image_0X.
std::optional<int> kitti_index_of(const fs::path& folder) {
  const std::string name = folder.filename().string();
  if (name.size() == 8 && name.starts_with("image_0") && is_digit(name.back())) {
    return name.back() - '0';
  }
  return std::nullopt;
}

// KITTI raw's image_0X folders in `folder`: the one asked for, else the only one, else image_02.
// `found` receives every image_0X present.
std::optional<fs::path> kitti_camera(const fs::path& folder, std::optional<int> camera_index,
                                     std::vector<fs::path>& found) {
  for (int index = 0; index < 10; ++index) {
    const fs::path path = folder / fmt::format("image_{:02d}", index);
    if (folder_exists(path)) found.push_back(path);
  }
  if (camera_index) {
    const fs::path path = folder / fmt::format("image_{:02d}", *camera_index);
    return folder_exists(path) ? std::optional<fs::path>(path) : std::nullopt;
  }
  if (found.size() == 1) return found.front();
  if (folder_exists(folder / "image_02")) return folder / "image_02";
  return std::nullopt;
}

std::string folder_names(const std::vector<fs::path>& folders) {
  std::string names;
  for (const fs::path& folder : folders) {
    names += (names.empty() ? "" : ", ") + folder.filename().string();
  }
  return names;
}

}  // namespace

ImageFolder list_images(const fs::path& folder, std::optional<int> camera_index) {
  if (camera_index && (*camera_index < 0 || *camera_index > 9)) {
    reject_argument("list_images: camera index {} is not 0-9", *camera_index);
  }
  if (!folder_exists(folder)) throw InputError(folder.string(), "is not a folder");
  if (folder_exists(folder / "camera")) {
    if (std::optional<ImageFolder> found = list_camera_folder(folder / "camera")) return *found;
  }
  std::vector<fs::path> cameras;
  if (const std::optional<fs::path> kitti = kitti_camera(folder, camera_index, cameras)) {
    std::optional<ImageFolder> found = list_camera_folder(*kitti);
    if (!found) {
      throw InputError(kitti->string(), "a KITTI camera folder holds data/ and timestamps.txt");
    }
    found->kitti_camera_index = kitti_index_of(*kitti);
    return *found;
  }
  if (!cameras.empty()) {
    throw InputError(
        folder.string(),
        camera_index
            ? fmt::format("has no image_{:02d}/ (KITTI raw camera {}); it holds {}", *camera_index,
                          *camera_index, folder_names(cameras))
            : fmt::format("holds several KITTI cameras ({}) and no image_02: choose one with "
                          "--camera-index",
                          folder_names(cameras)));
  }
  // "DIR/data/" names the same folder as "DIR/data": its parent is DIR either way.
  const fs::path named = folder.filename().empty() ? folder.parent_path() : folder;
  // The folder may be KITTI's camera folder image_0X/ itself, or its data/.
  std::optional<int> own_index = kitti_index_of(named);
  if (!own_index && named.filename() == "data") own_index = kitti_index_of(named.parent_path());
  if (own_index && camera_index && *own_index != *camera_index) {
    throw InputError(folder.string(),
                     fmt::format("holds KITTI camera {}'s images (image_{:02d}), not camera {}'s",
                                 *own_index, *own_index, *camera_index));
  }
  std::optional<ImageFolder> found = list_camera_folder(folder);
  if (!found) {
    std::optional<fs::path> timestamps = existing_file(folder / "timestamps.txt");
    if (!timestamps) timestamps = existing_file(named.parent_path() / "timestamps.txt");
    found = list_with_times(folder, timestamps);
  }
  found->kitti_camera_index = own_index;
  return *found;
}

}  // namespace x2car::io
