// Simulated spinning LiDAR (issue 3: a 60 s urban drive with a 64-beam LiDAR, 600 sweeps of ~100 k
// points, written in <= 60 s on a 2-core machine): time per minute of data to make the sweeps, to
// make and write them as binary PCD, and to generate and mesh the world.
#include <benchmark/benchmark.h>

#include <atomic>
#include <filesystem>

#include "x2car/sim/lidar_writer.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car {
namespace {

sim::SimulationOptions urban_lidar_drive(double duration_s, int beams) {
  sim::SimulationOptions options;
  options.scenario = sim::Scenario::kUrban;
  options.duration_s = duration_s;
  options.seed = 1;
  options.sensors = {"lidar"};
  options.lidar.beams = beams;
  return options;
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

}  // namespace
}  // namespace x2car
