#include "x2car/sim/camera_writer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "x2car/io/text_lines.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car::sim {
namespace {

namespace fs = std::filesystem;

TEST(CameraWriter, FrameFilesAreNamedLikeKittiRaw) {
  EXPECT_EQ(camera_frame_file_name(0, CameraImageFormat::kPng), "0000000000.png");
  EXPECT_EQ(camera_frame_file_name(12, CameraImageFormat::kJpeg), "0000000012.jpg");
  EXPECT_EQ(camera_image_format_from_string("jpg"), CameraImageFormat::kJpeg);
  EXPECT_THROW(camera_image_format_from_string("bmp"), std::invalid_argument);
}

TEST(CameraWriter, TimestampsAreKittiRawUtcWithNanoseconds) {
  // 2026-06-01 10:00:00 UTC.
  EXPECT_EQ(kitti_timestamp(1780308000.0, 0.1), "2026-06-01 10:00:00.100000000");
  EXPECT_EQ(kitti_timestamp(1780308000.0, 59.9), "2026-06-01 10:00:59.900000000");
  // A leap day, a fraction in the start, and a carry into the next day.
  EXPECT_EQ(kitti_timestamp(951782400.25, 0.5), "2000-02-29 00:00:00.750000000");
  EXPECT_EQ(kitti_timestamp(951868799.5, 0.75), "2000-03-01 00:00:00.250000000");
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every file under `folder` by its path relative to it, with its bytes.
std::map<std::string, std::string> folder_bytes(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (entry.is_regular_file()) {
      files[fs::relative(entry.path(), folder).string()] = file_bytes(entry.path());
    }
  }
  return files;
}

// A short drive with a small camera (fast): 0.5 s, 5 frames of 200x60.
SimulationOptions small_camera_drive(std::vector<std::string> sensors) {
  SimulationOptions options;
  options.duration_s = 0.5;
  options.seed = 3;
  options.sensors = std::move(sensors);
  core::CameraIntrinsics& camera = options.camera.intrinsics;
  camera.width = 200;
  camera.height = 60;
  camera.fx = camera.fy = 120.0;
  camera.cx = 99.5;
  camera.cy = 29.5;
  options.lidar.beams = 32;
  options.lidar.azimuth_step = rad_from_deg(2.0);
  return options;
}

fs::path written(const SimulationOptions& options, const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / name;
  fs::remove_all(folder);
  write_simulation(simulate(options), folder);
  return folder;
}

TEST(SimulatedCamera, WritesFramesTimestampsAndLabelsByteIdenticallyForTheSameArguments) {
  const SimulationOptions options = small_camera_drive({"camera"});
  const fs::path a = written(options, "camera_writer_a");
  const fs::path b = written(options, "camera_writer_b");
  const auto files = folder_bytes(a / "camera");
  EXPECT_EQ(files, folder_bytes(b / "camera"));
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(files.contains("images/" + camera_frame_file_name(i, CameraImageFormat::kPng)))
        << i;
  }
  EXPECT_FALSE(files.contains("images/0000000005.png"));
  const RgbImage image = read_image(a / "camera/images/0000000004.png");
  EXPECT_EQ(image.width, 200);
  EXPECT_EQ(image.height, 60);
  EXPECT_EQ(files.at("timestamps.txt"),
            "2026-06-01 10:00:00.000000000\n2026-06-01 10:00:00.100000000\n"
            "2026-06-01 10:00:00.200000000\n2026-06-01 10:00:00.300000000\n"
            "2026-06-01 10:00:00.400000000\n");
  const std::string& labels = files.at(kCameraLabelsFile);
  EXPECT_EQ(std::count(labels.begin(), labels.end(), '\n'), 6);  // header + 5 frames
  EXPECT_THAT(labels, ::testing::HasSubstr("\n0.4,"));
}

TEST(SimulatedCamera, WritesJpegWhenAsked) {
  SimulationOptions options = small_camera_drive({"camera"});
  options.camera_render.format = CameraImageFormat::kJpeg;
  const fs::path folder = written(options, "camera_writer_jpeg");
  EXPECT_TRUE(fs::exists(folder / "camera/images/0000000000.jpg"));
  EXPECT_FALSE(fs::exists(folder / "camera/images/0000000000.png"));
  EXPECT_EQ(read_image(folder / "camera/images/0000000002.jpg").width, 200);
}

TEST(SimulatedCamera, AddingTheCameraChangesNoOtherSensorsBytes) {
  const fs::path without = written(small_camera_drive({"ins", "lidar", "radar"}), "camera_without");
  const fs::path with =
      written(small_camera_drive({"ins", "lidar", "radar", "camera"}), "camera_with");
  auto others = [](const fs::path& folder) {
    auto files = folder_bytes(folder);
    std::erase_if(files, [](const auto& file) {
      return file.first.starts_with("camera") || file.first == "ground_truth.yaml";
    });
    return files;
  };
  const auto files = others(without);
  EXPECT_GT(files.size(), 5u);
  EXPECT_EQ(others(with), files);
}

}  // namespace
}  // namespace x2car::sim
