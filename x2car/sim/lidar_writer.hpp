// Writing simulated LiDAR sweeps to a drive's `lidar/` folder (docs/formats.md):
//   lidar/<start>.pcd            one binary PCD per sweep (io/pcd.hpp), named by the sweep's start
//                                time in seconds since the log's start, 6 decimals, the integer
//                                part zero-padded to 6 digits: 000012.300000.pcd
//   lidar/velodyne/NNNNNN.bin    KITTI scans, numbered from 000000 (io/kitti_velodyne.hpp)
//   lidar/times.txt              KITTI: each scan's start time [s], one per line
// Sweeps are written as they are made, in parallel, so a long drive never holds more than a few in
// memory. The bytes depend only on the simulator's arguments.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/world.hpp"

namespace x2car::sim {

enum class LidarFileFormat { kPcd, kKitti, kBoth };

std::string to_string(LidarFileFormat format);  // "pcd", "kitti", "both"
// Inverse of to_string; throws std::invalid_argument listing the valid names.
LidarFileFormat lidar_file_format_from_string(std::string_view name);
std::vector<std::string> lidar_file_format_names();  // the CLI's choices, in table order

// "000012.300000.pcd" for a sweep starting 12.3 s into the log.
std::string lidar_sweep_file_name(double start_time_s);

// What `simulate` needs to make and write the LiDAR's data.
struct LidarOutput {
  LidarOptions options;
  LidarFileFormat format = LidarFileFormat::kPcd;
  std::uint64_t seed = 0;  // of the LiDAR's noise and dropouts
};

struct LidarWriteSummary {
  std::size_t sweeps = 0;
  std::size_t points = 0;
};

// Sweeps written and the total, e.g. for a progress bar; called under a lock, `done` increasing.
// Must not throw.
using SweepProgress = std::function<void(std::size_t done, std::size_t total)>;

// Writes every sweep of `lidar` into `folder` (created). InputError when it cannot be written.
LidarWriteSummary write_lidar_sweeps(const LidarSimulator& lidar,
                                     const std::filesystem::path& folder, LidarFileFormat format,
                                     const SweepProgress& progress = {});

// Builds the world's Embree scene and writes the LiDAR at `vehicle_from_lidar` driven along
// `states` into `folder`.
LidarWriteSummary write_simulated_lidar(const World& world, const VehicleStates& states,
                                        const Eigen::Isometry3d& vehicle_from_lidar,
                                        const LidarOutput& output,
                                        const std::filesystem::path& folder,
                                        const SweepProgress& progress = {});

}  // namespace x2car::sim
