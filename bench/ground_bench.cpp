// Ground-plane fit (issue 5: "bench/ reports ground ms per sweep"): one thread, default options,
// on simulated urban sweeps of 32, 64 and 128 beams, reusing the scratch buffers as the calibrator
// does. The fit is the per-sweep cost; the per-sweep accuracy study is x2car_ground_study.
#include <benchmark/benchmark.h>

#include "x2car/lidar/ground.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car {
namespace {

// Arg: beams. 20 sweeps spread over a 20 s urban drive, fitted in turn.
void BM_FitGround(benchmark::State& state) {
  const sim::Simulation simulation = sim::simulate(sim::testing::simulated_lidar_drive(
      sim::Scenario::kUrban, 20.0, static_cast<int>(state.range(0)), 1));
  const sim::WorldScene scene(simulation.world);
  const sim::LidarSimulator lidar(
      scene, simulation.states,
      simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor(),
      simulation.lidar->options, simulation.lidar->seed);
  std::vector<io::PointCloud> sweeps;
  for (std::size_t i = 0; i < lidar.sweep_count(); i += 10) sweeps.push_back(lidar.sweep(i).cloud);
  const lidar::GroundOptions ground;
  lidar::GroundScratch scratch;
  std::size_t next = 0, points = 0, failures = 0;
  for (auto _ : state) {
    const io::PointCloud& sweep = sweeps[next];
    const lidar::GroundFit fit = lidar::fit_ground(sweep, ground, next, scratch);
    benchmark::DoNotOptimize(fit);
    points += sweep.points.size();
    failures += fit.plane ? 0 : 1;
    next = (next + 1) % sweeps.size();
  }
  state.counters["points_per_sweep"] =
      benchmark::Counter(static_cast<double>(points), benchmark::Counter::kAvgIterations);
  state.counters["failures"] = static_cast<double>(failures);
}
BENCHMARK(BM_FitGround)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace x2car
