#include "x2car/camera/camera_frames.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera {
namespace {

namespace fs = std::filesystem;
using x2car::testing::AngleNearDeg;
using x2car::testing::expect_input_error;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("camera_frames_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

// A drive written as the simulator writes it (camera/images/NNNNNNNNNN.png + timestamps.txt),
// read back and calibrated: the whole path from files to angles.
TEST(CameraFrames, CalibratesADriveFromPngFiles) {
  const fs::path drive = fresh_folder("drive");
  fs::create_directories(drive / "camera/images");
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(-1.0), rad_from_deg(2.0), rad_from_deg(3.0)};
  std::string timestamps;
  for (int i = 0; i < 24; ++i) {
    testing::StreetScene scene;
    scene.vehicle_from_camera = mounting;
    scene.travelled_m = 1.0 * i;  // 10 m/s: a car standing still would be refused
    scene.noise_seed = static_cast<std::uint64_t>(i + 1);
    cv::imwrite((drive / fmt::format("camera/images/{:010d}.png", i)).string(),
                testing::draw_street(scene, intrinsics));
    timestamps += fmt::format("2026-01-02 10:00:{:02d}.{:01d}00000000\n", i / 10, i % 10);
  }
  io::write_text_file(drive / "camera/timestamps.txt", timestamps);
  const io::ImageFolder folder = io::list_images(drive);
  ASSERT_EQ(folder.images.size(), 24U);
  CameraCalibrationOptions options;
  options.filter.window_frames = 12;
  const CalibrationResult result =
      calibrate_camera(camera_frames_from(folder), intrinsics, options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_THAT(*result.roll, AngleNearDeg(mounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(mounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(mounting.yaw, 0.1));
}

TEST(CameraFrames, ABrokenImageNamesItsFile) {
  const fs::path folder = fresh_folder("broken");
  io::write_text_file(folder / "1.500000.png", "\x89PNG truncated");
  expect_input_error([&] { read_grey_image(folder / "1.500000.png"); },
                     (folder / "1.500000.png").string(), 0);
  const io::ImageFolder images = io::list_images(folder);
  const CameraFrameSource frames = camera_frames_from(images);
  expect_input_error([&] { frames.read(0); }, (folder / "1.500000.png").string(), 0);
  EXPECT_EQ(frames.name(0), (folder / "1.500000.png").string());
}

// A JPEG cut short decodes without an error (its missing rows grey) and was taken as a good frame;
// it names its file now, and a whole one still reads.
TEST(CameraFrames, AJpegCutShortNamesItsFile) {
  const fs::path folder = fresh_folder("jpeg_cut_short");
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  std::vector<unsigned char> bytes;
  ASSERT_TRUE(cv::imencode(".jpg", testing::draw_street({}, intrinsics), bytes));
  const auto write = [&](const fs::path& path, std::size_t size) {
    io::write_text_file(path, std::string(bytes.begin(), bytes.begin() + static_cast<long>(size)));
  };
  write(folder / "whole.jpg", bytes.size());
  EXPECT_EQ(read_grey_image(folder / "whole.jpg").cols, intrinsics.width);
  write(folder / "cut.jpg", bytes.size() * 2 / 3);
  ASSERT_FALSE(cv::imread((folder / "cut.jpg").string(), cv::IMREAD_GRAYSCALE).empty());
  const InputError cut = expect_input_error([&] { read_grey_image(folder / "cut.jpg"); },
                                            (folder / "cut.jpg").string(), 0);
  EXPECT_THAT(cut.what(), ::testing::HasSubstr("JPEG cut short"));
  write(folder / "no_end.jpg", bytes.size() - 2);  // only the end-of-image marker missing
  expect_input_error([&] { read_grey_image(folder / "no_end.jpg"); },
                     (folder / "no_end.jpg").string(), 0);
}

// JPEG files are coded with loss (the motion estimator then tracks with its larger window); PNG
// files are not.
TEST(CameraFrames, JpegFilesAreLossy) {
  const fs::path folder = fresh_folder("lossy");
  const cv::Mat grey(8, 8, CV_8UC1, cv::Scalar(100));
  cv::imwrite((folder / "1.000000.png").string(), grey);
  const io::ImageFolder png = io::list_images(folder);
  EXPECT_FALSE(camera_frames_from(png).lossy);
  cv::imwrite((folder / "1.100000.JPG").string(), grey);
  const io::ImageFolder mixed = io::list_images(folder);
  ASSERT_EQ(mixed.images.size(), 2U);
  EXPECT_TRUE(camera_frames_from(mixed).lossy);
}

}  // namespace
}  // namespace x2car::camera
