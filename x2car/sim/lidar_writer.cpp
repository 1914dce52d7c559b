#include "x2car/sim/lidar_writer.hpp"

#include <fmt/format.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/kitti_velodyne.hpp"
#include "x2car/io/pcd.hpp"

namespace x2car::sim {
namespace {

void create_folder(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder.string(), "cannot create the folder: " + error.message());
}

}  // namespace

constexpr std::array<EnumName<LidarFileFormat>, 3> kLidarFileFormatNames{{
    {LidarFileFormat::kPcd, "pcd"},
    {LidarFileFormat::kKitti, "kitti"},
    {LidarFileFormat::kBoth, "both"},
}};

std::string to_string(LidarFileFormat format) {
  return enum_to_string(kLidarFileFormatNames, format);
}

LidarFileFormat lidar_file_format_from_string(std::string_view name) {
  return enum_from_string(kLidarFileFormatNames, name, "LiDAR file format");
}

std::vector<std::string> lidar_file_format_names() { return enum_names(kLidarFileFormatNames); }

std::string lidar_sweep_file_name(double start_time_s) {
  return fmt::format("{:013.6f}.pcd", start_time_s);
}

LidarWriteSummary write_lidar_sweeps(const LidarSimulator& lidar,
                                     const std::filesystem::path& folder, LidarFileFormat format,
                                     const SweepProgress& progress) {
  const bool pcd = format != LidarFileFormat::kKitti;
  const bool kitti = format != LidarFileFormat::kPcd;
  create_folder(folder);
  if (kitti) create_folder(folder / "velodyne");
  std::atomic<std::size_t> points{0};
  std::mutex progress_mutex;
  std::size_t done = 0;
  for_each_lidar_sweep(lidar, [&](LidarSweep&& sweep) {
    points += sweep.cloud.points.size();
    if (pcd) io::write_pcd(folder / lidar_sweep_file_name(sweep.start_time), sweep.cloud);
    if (kitti) {
      io::write_kitti_velodyne(folder / "velodyne" / fmt::format("{:06d}.bin", sweep.index),
                               sweep.cloud);
    }
    if (progress) {
      const std::lock_guard lock(progress_mutex);
      progress(++done, lidar.sweep_count());
    }
  });
  if (kitti) {
    std::vector<double> times(lidar.sweep_count());
    for (std::size_t i = 0; i < times.size(); ++i) times[i] = lidar.sweep_start_time(i);
    io::write_kitti_times(folder / "times.txt", times);
  }
  return {lidar.sweep_count(), points.load()};
}

LidarWriteSummary write_simulated_lidar(const World& world, const VehicleStates& states,
                                        const Eigen::Isometry3d& vehicle_from_lidar,
                                        const LidarOutput& output,
                                        const std::filesystem::path& folder,
                                        const SweepProgress& progress) {
  const WorldScene scene(world);
  const LidarSimulator lidar(scene, states, vehicle_from_lidar, output.options, output.seed);
  return write_lidar_sweeps(lidar, folder, output.format, progress);
}

}  // namespace x2car::sim
