#include "x2car/io/kitti_velodyne.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/point_cloud.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using x2car::testing::expect_input_error;

TEST(KittiVelodyne, RoundTripsPointsAndTimes) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "kitti_velodyne";
  std::filesystem::create_directories(folder);
  PointCloud cloud;
  cloud.has_intensity = true;
  for (int i = 0; i < 50; ++i) {
    const float f = static_cast<float>(i);
    cloud.points.push_back({0.5f * f - 10.0f, 3.0f - 0.25f * f, -1.7f, 0.02f * f, 0, 0.0f});
  }
  write_kitti_velodyne(folder / "000000.bin", cloud);
  EXPECT_EQ(std::filesystem::file_size(folder / "000000.bin"), 16 * cloud.points.size());
  const PointCloud read = read_kitti_velodyne(folder / "000000.bin");
  ASSERT_EQ(read.points.size(), cloud.points.size());
  EXPECT_EQ(read.points[10].y, cloud.points[10].y);
  EXPECT_NEAR(read.points[10].intensity, cloud.points[10].intensity, 1e-4);
  const std::vector<double> times = {0.0, 0.1, 0.2};
  EXPECT_EQ(format_kitti_times(times), "0.000000e+00\n1.000000e-01\n2.000000e-01\n");
  write_text_file(folder / "broken.bin", "0123456789");
  expect_input_error([&] { read_kitti_velodyne(folder / "broken.bin"); },
                     (folder / "broken.bin").string(), 0);
}

}  // namespace
}  // namespace x2car::io
