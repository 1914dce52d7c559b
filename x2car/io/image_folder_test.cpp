#include "x2car/io/image_folder.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using x2car::testing::expect_input_error;
using x2car::testing::input_error_of;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("image_folder_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

// Listing never decodes, so any bytes do for an image here.
void touch(const fs::path& path) {
  fs::create_directories(path.parent_path());
  write_text_file(path, "not decoded\n");
}

std::vector<double> times_of(const ImageFolder& folder) {
  std::vector<double> times;
  for (const ImageFile& image : folder.images) times.push_back(image.time);
  return times;
}

TEST(FileExtension, IsLowerCaseWithItsDot) {
  EXPECT_EQ(lower_case_extension("frame.PNG"), ".png");
  EXPECT_EQ(lower_case_extension("/drive/run.Mp4"), ".mp4");
  EXPECT_EQ(lower_case_extension("sweeps/0001.tar.GZ"), ".gz");
  EXPECT_EQ(lower_case_extension("README"), "");
  EXPECT_TRUE(is_jpeg_file("a/B.JPEG"));
  EXPECT_FALSE(is_jpeg_file("a/b.png"));
}

TEST(ImageFolder, ReadsASimulatedDriveFolderWithKittiTimestamps) {
  const fs::path drive = fresh_folder("simulated");
  touch(drive / "camera/images/0000000000.png");
  touch(drive / "camera/images/0000000001.png");
  touch(drive / "camera/intrinsics.yaml");
  write_text_file(drive / "camera/timestamps.txt",
                  "2011-09-26 13:02:25.594360375\n2011-09-26 13:02:25.698000000\n");
  const ImageFolder folder = list_images(drive);
  EXPECT_EQ(folder.folder, drive / "camera/images");
  ASSERT_EQ(folder.images.size(), 2U);
  EXPECT_EQ(folder.images[1].path, drive / "camera/images/0000000001.png");
  // Unix seconds of 2011-09-26 13:02:25.594360375 UTC.
  EXPECT_NEAR(folder.images[0].time, 1317042145.594360375, 1e-6);
  EXPECT_NEAR(folder.images[1].time - folder.images[0].time, 0.103639625, 1e-6);
  EXPECT_EQ(folder.time_source, (drive / "camera/timestamps.txt").string());
}

TEST(ImageFolder, PicksTheKittiCameraAskedFor) {
  const fs::path drive = fresh_folder("kitti");
  for (const char* camera : {"image_00", "image_02"}) {
    touch(drive / camera / "data/0000000000.png");
    write_text_file(drive / camera / "timestamps.txt", "2011-09-26 13:02:25.5\n");
  }
  EXPECT_EQ(list_images(drive).folder, drive / "image_02/data");  // KITTI's left colour camera
  EXPECT_EQ(list_images(drive, 0).folder, drive / "image_00/data");
  expect_input_error([&] { list_images(drive, 3); }, drive.string(), 0);
  EXPECT_THROW(list_images(drive, 12), std::invalid_argument);
  // The data folder itself finds timestamps.txt one level up.
  EXPECT_EQ(list_images(drive / "image_00/data/").images.size(), 1U);
}

TEST(ImageFolder, SaysWhichKittiCameraItsImagesAre) {
  const fs::path drive = fresh_folder("kitti_index");
  touch(drive / "image_03/data/0000000000.png");
  write_text_file(drive / "image_03/timestamps.txt", "2011-09-26 13:02:25.5\n");
  // The only camera of the drive is camera 3: its images take the _03 calibration keys.
  EXPECT_EQ(list_images(drive).kitti_camera_index, 3);
  // The camera folder itself, or its data/, with or without the index.
  EXPECT_EQ(list_images(drive / "image_03").kitti_camera_index, 3);
  EXPECT_EQ(list_images(drive / "image_03", 3).folder, drive / "image_03/data");
  EXPECT_EQ(list_images(drive / "image_03/data/", 3).kitti_camera_index, 3);
  EXPECT_EQ(list_images(drive / "image_03/data").timestamps_file,
            drive / "image_03/timestamps.txt");
  // Camera 2's keys for camera 3's images: refused, naming the folder.
  const InputError other = input_error_of([&] { list_images(drive / "image_03", 2); });
  EXPECT_THAT(other.what(), HasSubstr("camera 3's images (image_03), not camera 2's"));
  // A drive with cameras 0 and 1 only: which one is the user's to say.
  const fs::path grey = fresh_folder("kitti_grey");
  for (const char* camera : {"image_00", "image_01"}) {
    touch(grey / camera / "data/0000000000.png");
    write_text_file(grey / camera / "timestamps.txt", "2011-09-26 13:02:25.5\n");
  }
  const InputError several = input_error_of([&] { list_images(grey); });
  EXPECT_THAT(several.what(), HasSubstr("several KITTI cameras (image_00, image_01)"));
  EXPECT_THAT(input_error_of([&] { list_images(grey, 2); }).what(),
              HasSubstr("has no image_02/ (KITTI raw camera 2); it holds image_00, image_01"));
  EXPECT_EQ(list_images(grey, 1).kitti_camera_index, 1);
  // A plain folder of images is no KITTI camera; an index then only picks calibration keys.
  const fs::path plain = fresh_folder("plain_index");
  touch(plain / "a.png");
  write_text_file(plain / "timestamps.txt", "1.0\n");
  EXPECT_EQ(list_images(plain).kitti_camera_index, std::nullopt);
  EXPECT_EQ(list_images(plain, 3).images.size(), 1U);
  EXPECT_EQ(list_images(plain, 3).kitti_camera_index, std::nullopt);
}

TEST(ImageFolder, OrdersNumberedNamesByTheirNumbers) {
  const fs::path folder = fresh_folder("unpadded");
  for (const char* name : {"frame_10.png", "frame_9.png", "frame_1.png", "frame_2.png"}) {
    touch(folder / name);
  }
  write_text_file(folder / "timestamps.txt", "1.0\n2.0\n3.0\n4.0\n");
  const ImageFolder images = list_images(folder);
  ASSERT_EQ(images.images.size(), 4U);
  std::vector<std::string> names;
  for (const ImageFile& image : images.images) names.push_back(image.path.filename().string());
  EXPECT_THAT(names, ElementsAre("frame_1.png", "frame_2.png", "frame_9.png", "frame_10.png"));
  EXPECT_EQ(images.timestamps_file, folder / "timestamps.txt");
}

TEST(ImageFolder, IgnoresHiddenFiles) {
  const fs::path folder = fresh_folder("hidden");
  touch(folder / "0000000000.png");
  touch(folder / "._0000000000.png");  // macOS's companion of a copied file
  write_text_file(folder / "timestamps.txt", "1.0\n");
  const ImageFolder images = list_images(folder);
  EXPECT_EQ(images.images.size(), 1U);
  EXPECT_EQ(images.ignored_files, 2U);  // the companion and timestamps.txt
}

TEST(ImageFolder, TakesTimesFromNamesWithoutATimestampsFile) {
  const fs::path folder = fresh_folder("names");
  touch(folder / "10.250000.png");
  touch(folder / "9.500000.JPG");
  touch(folder / "1541234567123456789.jpeg");
  touch(folder / "notes.txt");
  const ImageFolder images = list_images(folder);
  EXPECT_THAT(times_of(images), ElementsAre(9.5, 10.25, 1541234567.123456789));
  EXPECT_EQ(images.ignored_files, 1U);
  EXPECT_EQ(images.time_source, "file names");
}

TEST(ImageFolder, TakesSecondsFromATimestampsFile) {
  const fs::path folder = fresh_folder("seconds");
  touch(folder / "a.png");
  touch(folder / "b.png");
  write_text_file(folder / "timestamps.txt", "12.5\n12.6\n");
  EXPECT_THAT(times_of(list_images(folder)), ElementsAre(12.5, 12.6));
}

TEST(ImageFolder, RejectsMissingOrBrokenTimes) {
  const fs::path folder = fresh_folder("broken");
  touch(folder / "0000000000.png");
  touch(folder / "0000000001.png");
  // Frame numbers are not times.
  expect_input_error([&] { list_images(folder); }, (folder / "0000000000.png").string(), 0,
                     "file name");
  write_text_file(folder / "timestamps.txt", "1.0\n");
  const InputError count = input_error_of([&] { list_images(folder); });
  EXPECT_THAT(count.what(), HasSubstr("holds 1 timestamps but"));
  // Which file has no time, or which times have no file, is named.
  EXPECT_THAT(count.what(), HasSubstr("the first image without a time is 0000000001.png (image 2"));
  write_text_file(folder / "timestamps.txt", "1.0\n1.1\n1.2\n");
  EXPECT_THAT(input_error_of([&] { list_images(folder); }).what(),
              HasSubstr("timestamps 3 on have no image (the last image is 0000000001.png)"));
  write_text_file(folder / "timestamps.txt", "1.0\nyesterday\n");
  expect_input_error([&] { list_images(folder); }, (folder / "timestamps.txt").string(), 2,
                     "timestamp");
  write_text_file(folder / "timestamps.txt", "2011-09-26 13:02:25.5\n2011-09-26 13:02:60.5\n");
  EXPECT_THAT(input_error_of([&] { list_images(folder); }).what(),
              HasSubstr("not a UTC date-time 'YYYY-MM-DD HH:MM:SS.fffffffff'"));
  expect_input_error([&] { list_images(folder); }, (folder / "timestamps.txt").string(), 2,
                     "timestamp");
  // Nanoseconds where seconds belong: refused, naming the line, not read as a 60-year gap.
  write_text_file(folder / "timestamps.txt", "1.0\n1780308000100000000\n");
  EXPECT_THAT(input_error_of([&] { list_images(folder); }).what(),
              HasSubstr("milliseconds or nanoseconds?"));
  expect_input_error([&] { list_images(folder); }, (folder / "timestamps.txt").string(), 2,
                     "timestamp");
  write_text_file(folder / "timestamps.txt", "2.0\n1.0\n");
  expect_input_error([&] { list_images(folder); }, (folder / "timestamps.txt").string(), 2,
                     "timestamp");
  // The times as written, not as seconds since 1970 (1317045745.5 for the first here).
  write_text_file(folder / "timestamps.txt", "2011-09-26 13:02:25.5\n2011-09-26 13:02:25.4\n");
  EXPECT_THAT(input_error_of([&] { list_images(folder); }).what(),
              HasSubstr("the time does not increase (line 1: '2011-09-26 13:02:25.5', line 2: "
                        "'2011-09-26 13:02:25.4')"));
  const fs::path empty = fresh_folder("empty");
  expect_input_error([&] { list_images(empty); }, empty.string(), 0);
  expect_input_error([&] { list_images(empty / "missing"); }, (empty / "missing").string(), 0);
}

}  // namespace
}  // namespace x2car::io
