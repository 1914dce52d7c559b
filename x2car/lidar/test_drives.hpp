// Simulated LiDAR drives for the LiDAR tests and benches: the sweeps of a drive made on demand
// (SimulatedLidarDrive), and the odometry run on them against the simulator's truth.
#pragma once

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <vector>

#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/odometry.hpp"
#include "x2car/lidar/odometry_error.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/world_scene.hpp"

namespace x2car::lidar::testing {

inline sim::SimulationOptions simulated_lidar_drive(sim::Scenario scenario, double duration_s,
                                                    int beams, std::uint64_t seed) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.duration_s = duration_s;
  options.seed = seed;
  options.sensors = {"lidar"};
  options.lidar.beams = beams;
  return options;
}

// A simulated drive and its LiDAR, whose sweeps are made when asked for (thread-safe), as a folder
// of files would be read.
class SimulatedLidarDrive {
 public:
  explicit SimulatedLidarDrive(const sim::SimulationOptions& drive)
      : simulation_(sim::simulate(drive)),
        scene_(simulation_.world),
        lidar_(scene_, simulation_.states, truth().vehicle_from_sensor(),
               simulation_.lidar->options, simulation_.lidar->seed) {}
  // The scene and the LiDAR refer to the simulation's members: the drive stays where it was made.
  SimulatedLidarDrive(const SimulatedLidarDrive&) = delete;
  SimulatedLidarDrive& operator=(const SimulatedLidarDrive&) = delete;

  const sim::LidarSimulator& lidar() const { return lidar_; }
  const io::SensorMounting& truth() const {
    return simulation_.truth.vehicle_from_sensor.at("lidar");
  }

  // The sweeps as the calibrator reads them; valid while this drive lives.
  SweepSource source() const {
    SweepSource source;
    for (std::size_t i = 0; i < lidar_.sweep_count(); ++i) {
      source.times.push_back(lidar_.sweep_start_time(i));
    }
    source.read = [this](std::size_t index) { return lidar_.sweep(index).cloud; };
    return source;
  }

 private:
  sim::Simulation simulation_;
  sim::WorldScene scene_;
  sim::LidarSimulator lidar_;
};

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
