// Speed of the simulator's vehicle motion: the longest route (highway, ~21 km) driven for 10 min
// at the full 100 Hz rate (route + motion; ~0.08 s in release on one core, was asserted < 0.5 s
// in a unit test).
//
// Speed of the camera (camera_render.hpp): frames of a 60 s urban drive at the default render
// options, rendered and PNG-encoded in parallel as `simulate` does (in memory, not written), with
// the "kitti" (1242x375) and "automotive_1080p" (1920x1080, plumb_bob) presets. 60 frames spread
// over the drive are made per iteration; per_minute is the time for a minute of frames at 10 Hz
// (600), scaled from them.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <atomic>

#include "x2car/sim/camera_render.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/vehicle_motion.hpp"

namespace x2car {
namespace {

void BM_VehicleMotionTenMinutesHighway(benchmark::State& state) {
  const sim::VehicleMotionOptions options;
  for (auto _ : state) {
    const sim::Route route = sim::generate_route(
        sim::Scenario::kHighway, sim::route_length_for(sim::Scenario::kHighway, 600.0, options), 1);
    const sim::VehicleStates states =
        sim::simulate_vehicle_motion(route, sim::Scenario::kHighway, 600.0, options, 1);
    benchmark::DoNotOptimize(states);
  }
  state.counters["per_minute"] = benchmark::Counter(
      10.0, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_VehicleMotionTenMinutesHighway)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CameraMinuteOfFrames(benchmark::State& state) {
  sim::SimulationOptions options;
  options.duration_s = 60.0;
  options.sensors = {"camera"};
  // 0: the default camera, KITTI's 1242x375; 1: automotive_1080p, 1920x1080 (plumb_bob).
  options.camera.intrinsics =
      core::camera_preset(state.range(0) == 0 ? "kitti" : "automotive_1080p");
  const core::CameraIntrinsics& intrinsics = options.camera.intrinsics;
  state.SetLabel(fmt::format("{}x{}", intrinsics.width, intrinsics.height));
  const sim::Simulation simulation = sim::simulate(options);
  const sim::WorldScene scene(simulation.world);
  const sim::CameraRenderer camera(
      scene, simulation.states,
      simulation.truth.vehicle_from_sensor.at("camera").vehicle_from_sensor(), intrinsics,
      simulation.camera_output->options, simulation.camera_output->seed);
  constexpr std::size_t kFrames = 60;
  const std::size_t step = camera.frame_count() / kFrames;
  std::atomic<std::size_t> bytes{0};
  for (auto _ : state) {
    tbb::parallel_for(std::size_t{0}, kFrames, [&](std::size_t k) {
      bytes += sim::encode_image(camera.render(k * step), sim::CameraImageFormat::kPng).size();
    });
  }
  state.counters["per_minute"] = benchmark::Counter(
      static_cast<double>(kFrames) / 600.0,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["png_kB"] = static_cast<double>(bytes.load()) /
                             (1000.0 * static_cast<double>(kFrames * state.iterations()));
}
BENCHMARK(BM_CameraMinuteOfFrames)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace x2car
