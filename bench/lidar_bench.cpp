// Simulated spinning LiDAR (issue 3: a 60 s urban drive with a 64-beam LiDAR, 600 sweeps of ~100 k
// points, written in <= 60 s on a 2-core machine): time per minute of data to make the sweeps, to
// make and write them as binary PCD, and to generate and mesh the world.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <filesystem>

#include "x2car/lidar/lidar_test_support.hpp"
#include "x2car/lidar/odometry_error.hpp"
#include "x2car/sim/lidar_writer.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car {
namespace {

sim::SimulationOptions urban_lidar_drive(double duration_s, int beams) {
  return sim::testing::simulated_lidar_drive(sim::Scenario::kUrban, duration_s, beams, 1);
}

// Adds the counter "per_minute": wall time per minute of recorded data.
void report_time_per_minute(benchmark::State& state, double minutes) {
  state.counters["per_minute"] = benchmark::Counter(
      minutes, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Arg: beams. Every sweep of a 20 s drive, in parallel, kept in memory only while counted.
void BM_LidarSweeps(benchmark::State& state) {
  const double duration_s = 20.0;
  const sim::Simulation simulation =
      sim::simulate(urban_lidar_drive(duration_s, static_cast<int>(state.range(0))));
  const sim::WorldScene scene(simulation.world);
  const sim::LidarSimulator lidar(
      scene, simulation.states,
      simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor(),
      simulation.lidar->options, simulation.lidar->seed);
  std::atomic<std::size_t> points{0};
  for (auto _ : state) {
    points = 0;
    sim::for_each_lidar_sweep(
        lidar, [&](sim::LidarSweep&& sweep) { points += sweep.cloud.points.size(); });
  }
  state.counters["points_per_sweep"] = static_cast<double>(points) / lidar.sweep_count();
  state.counters["triangles"] = static_cast<double>(scene.triangle_count());
  report_time_per_minute(state, duration_s / 60.0);
}
BENCHMARK(BM_LidarSweeps)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

// The run: world, scene, 64-beam sweeps and their PCD files, for a 60 s urban drive.
void BM_SimulateAndWriteLidarMinute(benchmark::State& state) {
  const auto folder = std::filesystem::temp_directory_path() / "x2car_lidar_bench";
  for (auto _ : state) {
    std::filesystem::remove_all(folder);
    const sim::Simulation simulation = sim::simulate(urban_lidar_drive(60.0, 64));
    sim::write_simulation(simulation, folder);
  }
  std::filesystem::remove_all(folder);
  report_time_per_minute(state, 1.0);
}
BENCHMARK(BM_SimulateAndWriteLidarMinute)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// World generation and its Embree scene for a 10-minute highway drive (the largest world).
void BM_HighwayWorldScene(benchmark::State& state) {
  sim::SimulationOptions options = urban_lidar_drive(600.0, 64);
  options.scenario = sim::Scenario::kHighway;
  const sim::Simulation simulation = sim::simulate(options);
  std::size_t triangles = 0;
  for (auto _ : state) {
    const sim::WorldScene scene(simulation.world);
    triangles = scene.triangle_count();
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["objects"] = static_cast<double>(simulation.world.objects.size());
  report_time_per_minute(state, 10.0);
}
BENCHMARK(BM_HighwayWorldScene)->Unit(benchmark::kMillisecond)->UseRealTime();

// LiDAR odometry (issue 5: >= 120 sweeps/s of 64-beam data on 2 cores, drift <= 1 %). Arg: beams.
// A 60 s urban drive (seed 1); only register_sweep is timed (the simulator makes the sweeps in
// between). Counters: Hz = sweeps per second of registration, drift_percent and
// rotation_deg_per_100m = KITTI-style relative errors over 25-400 m, iterations per sweep,
// non_ok = sweeps whose registration reported a failure, weakest_constraint = the smallest
// translation or rotation constraint met (OdometryOptions::min_translation_constraint).
void BM_LidarOdometry(benchmark::State& state) {
  const sim::SimulationOptions drive = lidar::testing::simulated_lidar_drive(
      sim::Scenario::kUrban, 60.0, static_cast<int>(state.range(0)), 1);
  lidar::testing::OdometryRun run;
  for (auto _ : state) {
    run = lidar::testing::run_simulated_odometry(drive).front();
    state.SetIterationTime(run.register_seconds);
  }
  lidar::DriftOptions lengths;
  lengths.lengths_m = {25.0, 50.0, 100.0, 200.0, 400.0};
  const lidar::Drift drift = lidar::relative_drift(run.estimate, run.truth, lengths);
  double iterations = 0.0;
  double non_ok = 0.0;
  double weakest = 1.0;
  for (const lidar::OdometryStep& step : run.steps) {
    iterations += step.iterations;
    if (step.status != lidar::RegistrationStatus::kFirstSweep) {
      weakest = std::min({weakest, step.translation_constraint, step.rotation_constraint});
    }
    if (step.status != lidar::RegistrationStatus::kOk &&
        step.status != lidar::RegistrationStatus::kFirstSweep) {
      ++non_ok;
    }
  }
  const double sweeps = static_cast<double>(run.steps.size());
  state.counters["Hz"] = sweeps / run.register_seconds;
  state.counters["drift_percent"] = drift.translation_percent;
  state.counters["rotation_deg_per_100m"] = drift.rotation_deg_per_100m;
  state.counters["path_m"] = drift.path_length_m;
  state.counters["iterations"] = iterations / sweeps;
  state.counters["points_per_sweep"] = static_cast<double>(run.points) / sweeps;
  state.counters["non_ok"] = non_ok;
  state.counters["weakest_constraint"] = weakest;
}
BENCHMARK(BM_LidarOdometry)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Unit(benchmark::kSecond)
    ->UseManualTime()
    ->Iterations(1);

}  // namespace
}  // namespace x2car
