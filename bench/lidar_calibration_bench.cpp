// LiDAR calibrator (issue 5): the whole pipeline on 60 s of 64-beam sweeps read from PCD files
// (target <= 10 s wall on 2 cores), and accuracy against the simulator's ground truth on urban 60 s
// drives, seeds 1-5, for 32, 64 and 128 beams (targets: |roll|, |pitch|, |yaw| <= 0.05 deg and
// |height| <= 1 cm; x2 for 32 beams).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

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

// The largest |error| of the calibrations added [deg, m]; false (and the state skipped with the
// reason) when one gave no angle.
struct LargestErrors {
  double roll = 0.0, pitch = 0.0, yaw = 0.0, height = 0.0;

  bool add(const sim::SimulationOptions& drive_options, benchmark::State& state) {
    const lidar::testing::SimulatedLidarDrive drive(drive_options);
    const io::SensorMounting& truth = drive.truth();
    lidar::LidarCalibrationOptions options;
    options.keep_series = false;
    const CalibrationResult result =
        lidar::calibrate_lidar(lidar::testing::sweep_source(drive), options);
    if (!result.roll || !result.pitch || !result.yaw || !result.z) {
      state.SkipWithError(result.reason.c_str());
      return false;
    }
    const auto error_deg = [](double estimate, double truth_rad) {
      return std::abs(deg_from_rad(angle_difference(estimate, truth_rad)));
    };
    roll = std::max(roll, error_deg(*result.roll, truth.rotation.roll));
    pitch = std::max(pitch, error_deg(*result.pitch, truth.rotation.pitch));
    yaw = std::max(yaw, error_deg(*result.yaw, truth.rotation.yaw));
    height = std::max(height, std::abs(*result.z - truth.translation.z()));
    return true;
  }
  void report(benchmark::State& state) const {
    state.counters["max_roll_err_deg"] = roll;
    state.counters["max_pitch_err_deg"] = pitch;
    state.counters["max_yaw_err_deg"] = yaw;
    state.counters["max_height_err_m"] = height;
  }
};

// Args: beams. Counters: the largest |error| over seeds 1-5 [deg, m].
void BM_LidarAccuracy(benchmark::State& state) {
  const int beams = static_cast<int>(state.range(0));
  LargestErrors errors;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      if (!errors.add(urban_drive(seed, beams), state)) return;
    }
  }
  state.SetLabel(std::to_string(beams) + " beams, urban 60 s, seeds 1-5 (sweeps made in memory)");
  errors.report(state);
}

// A LiDAR mounted at any yaw (roofs carry them with the cable to the back or a side): the drives
// of BM_LidarAccuracy at 32 beams, the LiDAR rolled 1 deg, pitched -1.5 deg and at 2 deg more
// than 45, 90, 135, 180 and -90 deg (seeds 1 to 5). Counters: the largest |error| [deg, m].
void BM_LidarAccuracyAtAnyYaw(benchmark::State& state) {
  const double yaws_deg[] = {45.0, 90.0, 135.0, 180.0, -90.0};
  LargestErrors errors;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      sim::SimulationOptions drive = urban_drive(seed, 32);
      drive.mountings["lidar"] = {
          Eigen::Vector3d(1.2, 0.0, 1.9),
          {rad_from_deg(1.0), rad_from_deg(-1.5), rad_from_deg(yaws_deg[seed - 1] + 2.0)}};
      if (!errors.add(drive, state)) return;
    }
  }
  state.SetLabel("32 beams, urban 60 s, seeds 1-5 at 45, 90, 135, 180, -90 deg");
  errors.report(state);
}
BENCHMARK(BM_LidarAccuracyAtAnyYaw)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_LidarAccuracy)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace x2car

namespace x2car {
namespace {

// Issue 12 item 6 ("use the turns"): simulated city drives (short blocks, a turn at most corners)
// cut into 1-minute segments, as the paper's protocol does; every segment with >= 20 s faster than
// 3 m/s should give a yaw within 0.1 deg. Args: beams, turns (0 use, 1 exclude: the paper's
// gates). Seeds 1-2, 180 s each (six minutes of sweeps, made twice: one odometry per segment).
// Counters: eligible segments, the share giving a yaw, the share within 0.1 deg, the largest and
// the median |error| [deg].
void BM_LidarYawPerMinute(benchmark::State& state) {
  const int beams = static_cast<int>(state.range(0));
  const bool exclude = state.range(1) != 0;
  lidar::LidarCalibrationOptions options;
  options.keep_series = false;
  if (exclude) options.alignment.turns.samples = TurnSamples::kExclude;
  int eligible = 0, with_yaw = 0, within = 0;
  std::vector<double> errors_deg;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      const lidar::testing::SimulatedLidarDrive drive(
          sim::testing::simulated_lidar_drive(sim::Scenario::kCity, 180.0, beams, seed));
      const lidar::SweepSource all = lidar::testing::sweep_source(drive);
      const sim::VehicleStates& states = drive.simulation().states;
      for (double begin = 0.0; begin + 60.0 <= 180.0 + 1e-9; begin += 60.0) {
        double moving = 0.0;
        for (std::size_t i = 1; i < states.size(); ++i) {
          if (states[i].time > begin && states[i].time <= begin + 60.0 &&
              std::abs(states[i].speed) > 3.0) {
            moving += states[i].time - states[i - 1].time;
          }
        }
        if (moving < 20.0) continue;
        ++eligible;
        lidar::SweepSource minute;
        std::vector<std::size_t> indices;
        for (std::size_t i = 0; i < all.times.size(); ++i) {
          if (all.times[i] >= begin && all.times[i] < begin + 60.0) {
            minute.times.push_back(all.times[i]);
            indices.push_back(i);
          }
        }
        minute.read = [&all, indices](std::size_t index) { return all.read(indices[index]); };
        const CalibrationResult result = lidar::calibrate_lidar(minute, options);
        if (!result.ok() || !result.yaw) continue;
        ++with_yaw;
        const double error =
            std::abs(deg_from_rad(angle_difference(*result.yaw, drive.truth().rotation.yaw)));
        errors_deg.push_back(error);
        if (error <= 0.1) ++within;
      }
    }
  }
  state.SetLabel(std::to_string(beams) + " beams, city, turns " + (exclude ? "excluded" : "used") +
                 ", 1-min segments of seeds 1-2 x 180 s");
  state.counters["segments"] = eligible;
  state.counters["with_yaw_share"] = eligible > 0 ? static_cast<double>(with_yaw) / eligible : 0.0;
  state.counters["within_0.1deg_share"] =
      eligible > 0 ? static_cast<double>(within) / eligible : 0.0;
  std::ranges::sort(errors_deg);
  state.counters["max_err_deg"] = errors_deg.empty() ? NAN : errors_deg.back();
  state.counters["median_err_deg"] = errors_deg.empty() ? NAN : errors_deg[errors_deg.size() / 2];
}
BENCHMARK(BM_LidarYawPerMinute)
    ->ArgsProduct({{32}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace x2car
