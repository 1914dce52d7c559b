#include "x2car/sim/lidar_writer.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "x2car/io/ground_truth.hpp"
#include "x2car/io/kitti_velodyne.hpp"
#include "x2car/io/pcd.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::sim {
namespace {

SimulationOptions short_lidar_drive(std::uint64_t seed) {
  SimulationOptions options =
      testing::simulated_drive(Scenario::kUrban, 1.0, seed, {"ins", "lidar"});
  options.lidar.azimuth_step = rad_from_deg(1.0);
  options.lidar_format = LidarFileFormat::kBoth;
  return options;
}

std::filesystem::path temp_folder(const std::string& name) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(path);
  return path;
}

TEST(LidarWriter, FileNamesAreTheStartSecondsZeroPadded) {
  EXPECT_EQ(lidar_sweep_file_name(0.0), "000000.000000.pcd");
  EXPECT_EQ(lidar_sweep_file_name(12.3), "000012.300000.pcd");
  EXPECT_EQ(lidar_sweep_file_name(1234.5), "001234.500000.pcd");
  EXPECT_EQ(lidar_file_format_from_string("both"), LidarFileFormat::kBoth);
  EXPECT_EQ(to_string(LidarFileFormat::kKitti), "kitti");
  EXPECT_THROW(lidar_file_format_from_string("las"), std::invalid_argument);
}

TEST(LidarWriter, SimulatedDriveWritesEverySweepTheSameWayTwice) {
  const auto first = temp_folder("lidar_writer_a");
  const auto second = temp_folder("lidar_writer_b");
  write_simulation(simulate(short_lidar_drive(3)), first);
  write_simulation(simulate(short_lidar_drive(3)), second);

  const io::GroundTruth truth = io::read_ground_truth(first / "ground_truth.yaml");
  ASSERT_TRUE(truth.vehicle_from_sensor.contains("lidar"));
  EXPECT_GE(truth.vehicle_from_sensor.at("lidar").translation.z(), 1.5);
  EXPECT_LE(truth.vehicle_from_sensor.at("lidar").translation.z(), 2.2);

  for (int k = 0; k < 10; ++k) {
    const std::string pcd = lidar_sweep_file_name(0.1 * k);
    const std::string bin = fmt::format("velodyne/{:06d}.bin", k);
    for (const std::string& name : {pcd, bin}) {
      ASSERT_TRUE(std::filesystem::exists(first / "lidar" / name)) << name;
      EXPECT_EQ(io::read_text_file(first / "lidar" / name),
                io::read_text_file(second / "lidar" / name))
          << name;
    }
    const io::PointCloud cloud = io::read_pcd(first / "lidar" / pcd);
    ASSERT_GT(cloud.points.size(), 5000u);
    EXPECT_EQ(io::read_kitti_velodyne(first / "lidar" / bin).points.size(), cloud.points.size());
    for (const io::LidarPoint& p : cloud.points) {
      ASSERT_LT(p.ring, 64);
      ASSERT_GE(p.t, 0.0f);
      ASSERT_LT(p.t, 0.1f);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(first / "lidar" / lidar_sweep_file_name(1.0)));
  EXPECT_EQ(io::split_lines(io::read_text_file(first / "lidar" / "times.txt")).size(), 10u);
}

}  // namespace
}  // namespace x2car::sim
