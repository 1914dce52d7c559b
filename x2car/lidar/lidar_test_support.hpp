// The LiDAR engines run on the drives of the one test-data factory (sim/test_drives.hpp), for the
// LiDAR tests and benches: a simulated drive's sweeps as the calibrator reads them, and the
// odometry run on them against the simulator's truth.
#pragma once

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <vector>

#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/odometry.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::lidar::testing {

using sim::testing::simulated_lidar_drive;
using sim::testing::SimulatedLidarDrive;

// The drive's sweeps as the calibrator reads them; valid while `drive` lives.
inline SweepSource sweep_source(const SimulatedLidarDrive& drive) {
  SweepSource source;
  source.times = drive.sweep_times();
  const sim::LidarSimulator* lidar = &drive.lidar();
  source.read = [lidar](std::size_t index) { return lidar->sweep(index).cloud; };
  return source;
}

struct OdometryRun {
  std::vector<OdometryStep> steps;
  std::vector<Eigen::Isometry3d> estimate;  // world_from_lidar per sweep
  std::vector<Eigen::Isometry3d> truth;     // the simulator's, at each step's time
  double register_seconds = 0.0;            // wall time spent in register_sweep only
  std::size_t points = 0;                   // in all sweeps
};

// Makes the drive's sweeps (in parallel batches, to bound memory) and registers them in order,
// with one odometry per options (the sweeps are made once for all).
inline std::vector<OdometryRun> run_simulated_odometry(
    const sim::SimulationOptions& drive, const std::vector<OdometryOptions>& options = {{}}) {
  const SimulatedLidarDrive simulated(drive);
  const sim::LidarSimulator& lidar = simulated.lidar();
  std::vector<LidarOdometry> odometries;
  for (const OdometryOptions& o : options) odometries.emplace_back(o);
  std::vector<OdometryRun> runs(options.size());
  constexpr std::size_t kBatch = 16;
  std::vector<sim::LidarSweep> batch(kBatch);
  for (std::size_t first = 0; first < lidar.sweep_count(); first += kBatch) {
    const std::size_t count = std::min(kBatch, lidar.sweep_count() - first);
    tbb::parallel_for(std::size_t{0}, count,
                      [&](std::size_t k) { batch[k] = lidar.sweep(first + k); });
    for (std::size_t k = 0; k < count; ++k) {
      for (std::size_t r = 0; r < runs.size(); ++r) {
        OdometryRun& run = runs[r];
        const auto start = std::chrono::steady_clock::now();
        const OdometryStep step = odometries[r].register_sweep(batch[k].cloud, batch[k].start_time);
        run.register_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        run.points += batch[k].cloud.points.size();
        run.steps.push_back(step);
        run.estimate.push_back(step.world_from_lidar);
        run.truth.push_back(lidar.world_from_lidar(step.time));
      }
    }
  }
  return runs;
}

}  // namespace x2car::lidar::testing
