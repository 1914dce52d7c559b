// Finding the frames of a camera log in a folder, in time order (docs/formats.md, "Camera
// images"). Decoding is the camera module's (camera/camera_frames.hpp); this lists files only.
//
// The folder `DIR` given may be
//   - a simulate-style drive folder: DIR/camera/images/ + DIR/camera/timestamps.txt;
//   - a KITTI raw drive: DIR/image_0X/data/ + DIR/image_0X/timestamps.txt (camera_index X; when
//     none is given, the only image_0X present, else image_02, KITTI's left colour camera; several
//     and no image_02 is an error that asks for the index);
//   - a camera folder itself: DIR/images/ or DIR/data/ + DIR/timestamps.txt (KITTI's image_0X/
//     too: a camera_index must then be X);
//   - a folder of images: DIR/*.png|jpg|jpeg (any case) with DIR/timestamps.txt or
//     DIR/../timestamps.txt, or with names that are times.
// timestamps.txt holds one time per image in name order, numbers in names compared as numbers
// (frame_2.png before frame_10.png; zero-padded names sort alike either way): a UTC date-time
// "YYYY-MM-DD HH:MM:SS.fffffffff" (KITTI raw, the simulator) or seconds ("12.3", Unix or any
// clock). Without one, the names must be times: seconds with a fraction ("1541234567.123456.png")
// or whole nanoseconds (16 digits or more). Other files, and hidden ones (".name": macOS's "._"
// companions of copied images), are ignored and counted.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace x2car::io {

struct ImageFile {
  std::filesystem::path path;
  double time = 0.0;  // [s]: Unix seconds for date-times, else the file's own clock
};

struct ImageFolder {
  std::filesystem::path folder;           // where the image files were found
  std::vector<ImageFile> images;          // strictly increasing time
  std::size_t ignored_files = 0;          // files that are not images
  std::string time_source;                // "file names" or the timestamps file's path, for reports
  std::filesystem::path timestamps_file;  // the timestamps file read; empty: times from the names
  // X when the images are KITTI raw's camera X (image_0X/data/, found in a drive folder or given
  // itself): which keys of calib_cam_to_cam.txt are theirs. Absent: not a KITTI camera folder.
  std::optional<int> kitti_camera_index;
};

// InputError naming the folder when it is missing or holds no images, and naming the file and line
// when a timestamp or a name does not parse, the times do not strictly increase, or timestamps.txt
// has a different number of lines than there are images; naming the folder when it holds several
// KITTI cameras but no image_02 and no camera_index is given, or when it is KITTI's camera folder
// image_0X/ (or its data/) and camera_index is not X. A camera_index outside 0-9 is
// std::invalid_argument. A camera_index for a folder that holds no image_0X/ and is none itself is
// no error: such a folder is listed as any other (the index then only picks calibration keys).
ImageFolder list_images(const std::filesystem::path& folder,
                        std::optional<int> camera_index = std::nullopt);

}  // namespace x2car::io
