// Runs the odometry on a simulated drive and compares it with the simulator's truth: shared by
// odometry_test.cpp and bench/lidar_bench.cpp.
#pragma once

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <vector>

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
  const sim::Simulation simulation = sim::simulate(drive);
  const sim::WorldScene scene(simulation.world);
  const sim::LidarSimulator lidar(
      scene, simulation.states,
      simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor(),
      simulation.lidar->options, simulation.lidar->seed);
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
