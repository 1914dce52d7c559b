#include "x2car/lidar/voxel_downsample.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace x2car::lidar {
namespace {

TEST(VoxelDownsampler, KeepsTheFirstPointOfEachVoxel) {
  const std::vector<Eigen::Vector3f> points = {
      {0.1f, 0.1f, 0.1f}, {0.9f, 0.2f, 0.3f}, {1.1f, 0.1f, 0.1f}, {-0.1f, 0.1f, 0.1f}};
  VoxelDownsampler downsampler;
  std::vector<Eigen::Vector3f> kept;
  downsampler.downsample(points, 1.0f, kept);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[0], points[0]);
  EXPECT_EQ(kept[1], points[2]);
  EXPECT_EQ(kept[2], points[3]);
  downsampler.downsample(points, 1.0f, kept);  // the table is reused, with nothing left over
  EXPECT_EQ(kept.size(), 3u);
}

}  // namespace
}  // namespace x2car::lidar
