// LiDAR calibrator (issue 5): the whole pipeline on 60 s of 64-beam sweeps read from PCD files
// (target <= 10 s wall on 2 cores), and accuracy against the simulator's ground truth on urban 60 s
// drives, seeds 1-5, for 32, 64 and 128 beams (targets: |roll|, |pitch|, |yaw| <= 0.05 deg and
// |height| <= 1 cm; x2 for 32 beams).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "x2car/lidar/lidar_calibration.hpp"
#include "x2car/lidar/lidar_test_support.hpp"
#include "x2car/lidar/sweep_folder.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car {
namespace {

sim::SimulationOptions urban_drive(std::uint64_t seed, int beams) {
  return sim::testing::simulated_lidar_drive(sim::Scenario::kUrban, 60.0, beams, seed,
                                             {"ins", "lidar"});
}

void BM_CalibrateLidarOneMinuteFromFiles(benchmark::State& state) {
  const auto folder = std::filesystem::temp_directory_path() / "x2car_lidar_calibration_bench";
  std::filesystem::remove_all(folder);
  sim::write_simulation(sim::simulate(urban_drive(1, 64)), folder);
  const lidar::SweepFolder sweeps = lidar::list_sweeps(folder);
  lidar::LidarCalibrationOptions options;
  options.keep_series = false;
  CalibrationResult result;
  for (auto _ : state) {
    result = lidar::calibrate_lidar(lidar::sweep_source_from(sweeps), options);
    benchmark::DoNotOptimize(result);
  }
  state.SetLabel(result.ok() ? "ok" : result.reason);
  state.counters["sweeps"] = static_cast<double>(sweeps.sweeps.size());
  std::filesystem::remove_all(folder);
}
BENCHMARK(BM_CalibrateLidarOneMinuteFromFiles)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(2);

// Args: beams. Counters: the largest |error| over seeds 1-5 [deg, m].
void BM_LidarAccuracy(benchmark::State& state) {
  const int beams = static_cast<int>(state.range(0));
  double max_roll = 0.0, max_pitch = 0.0, max_yaw = 0.0, max_height = 0.0;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const lidar::testing::SimulatedLidarDrive drive(urban_drive(seed, beams));
      const io::SensorMounting& truth = drive.truth();
      lidar::LidarCalibrationOptions options;
      options.keep_series = false;
      const CalibrationResult result =
          lidar::calibrate_lidar(lidar::testing::sweep_source(drive), options);
      if (!result.roll || !result.pitch || !result.yaw || !result.z) {
        state.SkipWithError(result.reason.c_str());
        return;
      }
      const auto error_deg = [](double estimate, double truth_rad) {
        return std::abs(deg_from_rad(angle_difference(estimate, truth_rad)));
      };
      max_roll = std::max(max_roll, error_deg(*result.roll, truth.rotation.roll));
      max_pitch = std::max(max_pitch, error_deg(*result.pitch, truth.rotation.pitch));
      max_yaw = std::max(max_yaw, error_deg(*result.yaw, truth.rotation.yaw));
      max_height = std::max(max_height, std::abs(*result.z - truth.translation.z()));
    }
  }
  state.SetLabel(std::to_string(beams) + " beams, urban 60 s, seeds 1-5 (sweeps made in memory)");
  state.counters["max_roll_err_deg"] = max_roll;
  state.counters["max_pitch_err_deg"] = max_pitch;
  state.counters["max_yaw_err_deg"] = max_yaw;
  state.counters["max_height_err_m"] = max_height;
}
BENCHMARK(BM_LidarAccuracy)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace x2car
