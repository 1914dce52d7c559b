// Reading LiDAR sweeps from bags (issue 17: sensor_msgs/PointCloud2 from a bag is no slower per
// point than the PCD folder reader; 1 minute of 64-beam data, MB/s next to the PCD reader's).
// One simulated urban drive of 60 s (64 beams, 10 Hz, seed 21), its lidar/ folder of binary PCD
// files, and the same sweeps in each container, each read whole on one thread:
//   BM_ReadPcdFolder          list_sweeps + read_sweep of every sweep
//   BM_ReadBag/<container>    sweeps_from_bag (its scan of the bag for the stamps) + source.read
//                             of every sweep: MCAP with zstd, lz4 or uncompressed chunks
//                             (write_pointcloud_mcap.mjs), a ROS 1 bag (write_ros1_bag,
//                             uncompressed) and a ROS 2 sqlite3 bag (write_ros2_bag.mjs).
// Counters, rates shown as "/s": points, per second; MB, points x 22 bytes (x2car's point:
// x y z intensity ring t, as the PCD files and the PointCloud2 messages store it) / 1e6 per
// second, the same bytes for every reader; file_MB, the bytes of the files read per second
// (compressed MCAP: fewer); per_minute, wall seconds per minute of data; scan_s (bags), the
// seconds of sweeps_from_bag alone, the rest being the reads.
// The drive and bags are made once (minutes: the simulator, node) in $X2CAR_BAG_BENCH_DIR or
// <temp>/x2car_bag_bench and reused; each file is read once before the timing, so that the numbers
// are of decoding from the page cache, not of the disk. A bag that cannot be made (node or the
// tests' npm packages missing, write_ros1_bag not built) skips its benchmark with the reason.
// Measured (2-core reference machine, idle), seconds per minute of data: PCD folder 0.67-0.74;
// ROS 1 0.57-0.64; ROS 2 sqlite3 0.64-0.71; MCAP uncompressed 0.45, lz4 1.71, zstd 2.30-2.40 (each
// compressed chunk decompressed once, when its sweep is read; lz4 also in the scan, its frames'
// blocks holding the whole chunk) (docs/formats.md, "Speed").
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "x2car/io/point_cloud.hpp"
#include "x2car/lidar/bag_sweeps.hpp"
#include "x2car/lidar/sweep_folder.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

#ifndef X2CAR_SOURCE_DIR
#error "X2CAR_SOURCE_DIR: the source tree, for tests/bags (bench/CMakeLists.txt)"
#endif
#ifndef X2CAR_WRITE_ROS1_BAG
#define X2CAR_WRITE_ROS1_BAG ""
#endif

namespace x2car {
namespace {

namespace fs = std::filesystem;

constexpr double kPointBytes = 22.0;  // x y z intensity (float32), ring (uint16), t (float32)
using Clock = std::chrono::steady_clock;

fs::path data_dir() {
  const char* dir = std::getenv("X2CAR_BAG_BENCH_DIR");
  return dir != nullptr && *dir != '\0' ? fs::path(dir)
                                        : fs::temp_directory_path() / "x2car_bag_bench";
}

std::string shell_quoted(const fs::path& path) {
  std::string out = "'";
  for (const char c : path.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Makes `output` by `make` unless a completed one is there (marked by `output`.done); returns an
// error, or empty.
template <typename Make>
std::string made(const fs::path& output, const Make& make) {
  const fs::path done = fs::path(output.string() + ".done");
  if (fs::exists(done) && fs::exists(output)) return {};
  fs::remove_all(output);
  fs::remove(done);
  std::string error;
  try {
    error = make();
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (error.empty()) std::ofstream(done) << "made by x2car_bag_read_bench\n";
  return error;
}

// Runs a shell command, its output to `log`; an error naming the command and log, or empty.
std::string run(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " >" + shell_quoted(log) + " 2>&1").c_str());
  if (status == 0) return {};
  return "'" + command + "' failed (status " + std::to_string(status) + "; see " + log.string() +
         ")";
}

// A file or folder to read, or why it could not be made.
struct Input {
  fs::path path;
  std::string error;
};

// The drive folder (its lidar/ the PCD sweeps), made once per process and kept on disk.
const Input& drive() {
  static const Input folder = [] {
    Input out{.path = data_dir() / "drive", .error = {}};
    fs::create_directories(data_dir());
    out.error = made(out.path, [&] {
      sim::write_simulation(sim::simulate(sim::testing::simulated_lidar_drive(
                                sim::Scenario::kUrban, 60.0, 64, 21, {"ins", "lidar"})),
                            out.path);
      return std::string();
    });
    return out;
  }();
  return folder;
}

bool have_node() { return std::system("command -v node >/dev/null 2>&1") == 0; }

// The bag of a container name (BM_ReadBag's argument), made from the drive when missing.
Input bag_for(const std::string& name) {
  static std::map<std::string, Input> bags;
  if (const auto found = bags.find(name); found != bags.end()) return found->second;
  if (!drive().error.empty()) return bags[name] = {.path = {}, .error = drive().error};
  const fs::path dir = data_dir();
  const fs::path bags_js = fs::path(X2CAR_SOURCE_DIR) / "tests" / "bags";
  const fs::path drive_dir = drive().path;
  const std::string node = "node " + shell_quoted(bags_js) + "/";
  const std::string writer = X2CAR_WRITE_ROS1_BAG;
  Input bag;
  std::string command;
  if (name.starts_with("mcap_")) {
    bag.path = dir / ("drive_" + name.substr(5) + ".mcap");
    command = node + "write_pointcloud_mcap.mjs " + shell_quoted(drive_dir / "lidar") + " " +
              shell_quoted(bag.path) + " --compression " + name.substr(5);
    if (!have_node()) bag.error = "node is missing (scripts/setup)";
  } else if (name == "ros1") {
    bag.path = dir / "drive.bag";
    command = shell_quoted(writer) + " " + shell_quoted(drive_dir) + " " + shell_quoted(bag.path) +
              " --compression none";
    if (writer.empty()) bag.error = "write_ros1_bag is not built (X2CAR_BUILD_TESTS=OFF)";
  } else if (name == "ros2") {
    bag.path = dir / "ros2_bag";
    command = node + "write_ros2_bag.mjs " + shell_quoted(drive_dir) + " " + shell_quoted(bag.path);
    if (!have_node()) bag.error = "node is missing (scripts/setup)";
  } else {
    bag.error = "unknown container " + name;
  }
  if (bag.error.empty()) {
    bag.error = made(bag.path, [&] { return run(command, dir / (name + ".log")); });
  }
  return bags[name] = bag;
}

// The bytes of a file, or of every file under a folder; each read once, so that the timed reads
// find them in the page cache.
std::uintmax_t read_through(const fs::path& path) {
  std::vector<fs::path> files;
  if (fs::is_directory(path)) {
    for (const auto& entry : fs::recursive_directory_iterator(path)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  } else {
    files.push_back(path);
  }
  std::uintmax_t bytes = 0;
  std::vector<char> buffer(1 << 20);
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
      bytes += static_cast<std::uintmax_t>(in.gcount());
    }
  }
  return bytes;
}

// Minutes of data in sweeps starting at `times` (the last one as long as the others).
double minutes_of(const std::vector<double>& times) {
  if (times.size() < 2) return 0.0;
  const double span = times.back() - times.front();
  return span * static_cast<double>(times.size()) / static_cast<double>(times.size() - 1) / 60.0;
}

void report(benchmark::State& state, std::size_t points, std::size_t sweeps,
            std::uintmax_t file_bytes, double minutes) {
  using benchmark::Counter;
  const auto per_iteration = [](double value) {
    return Counter(value, Counter::kIsIterationInvariantRate);
  };
  state.counters["points"] = per_iteration(static_cast<double>(points));
  state.counters["MB"] = per_iteration(static_cast<double>(points) * kPointBytes / 1e6);
  state.counters["file_MB"] = per_iteration(static_cast<double>(file_bytes) / 1e6);
  state.counters["per_minute"] =
      Counter(minutes, Counter::kIsIterationInvariantRate | Counter::kInvert);
  state.SetLabel(std::to_string(sweeps) + " sweeps, " + std::to_string(points) + " points, " +
                 std::to_string(file_bytes / 1'000'000) + " MB of files");
}

// Skips the benchmark with `error`: the loop still has to run.
void skip(benchmark::State& state, const std::string& error) {
  state.SkipWithError(error.c_str());
  for (auto _ : state) {
  }
}

void BM_ReadPcdFolder(benchmark::State& state) {
  if (!drive().error.empty()) return skip(state, drive().error);
  const fs::path folder = drive().path / "lidar";
  const std::uintmax_t file_bytes = read_through(folder);
  std::size_t points = 0, sweeps = 0;
  double minutes = 0.0;
  for (auto _ : state) {
    try {
      const lidar::SweepFolder listed = lidar::list_sweeps(folder);
      points = 0;
      for (const lidar::SweepFile& sweep : listed.sweeps) {
        const io::PointCloud cloud = lidar::read_sweep(listed, sweep);
        points += cloud.points.size();
        benchmark::DoNotOptimize(cloud.points.data());
      }
      sweeps = listed.sweeps.size();
      std::vector<double> times;
      for (const lidar::SweepFile& sweep : listed.sweeps) times.push_back(sweep.time);
      minutes = minutes_of(times);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
  report(state, points, sweeps, file_bytes, minutes);
}
BENCHMARK(BM_ReadPcdFolder)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// Arg (by name): mcap_zstd, mcap_lz4, mcap_none, ros1, ros2.
void BM_ReadBag(benchmark::State& state, const std::string& container) {
  const Input bag = bag_for(container);
  if (!bag.error.empty()) return skip(state, bag.error);
  const std::uintmax_t file_bytes = read_through(bag.path);
  std::size_t points = 0, sweeps = 0;
  double minutes = 0.0, scan_s = 0.0;
  for (auto _ : state) {
    try {
      const Clock::time_point start = Clock::now();
      const lidar::BagSweeps found = lidar::sweeps_from_bag(bag.path);
      scan_s += std::chrono::duration<double>(Clock::now() - start).count();
      points = 0;
      for (std::size_t i = 0; i < found.source.times.size(); ++i) {
        const io::PointCloud cloud = found.source.read(i);
        points += cloud.points.size();
        benchmark::DoNotOptimize(cloud.points.data());
      }
      sweeps = found.source.times.size();
      minutes = minutes_of(found.source.times);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
  report(state, points, sweeps, file_bytes, minutes);
  state.counters["scan_s"] = benchmark::Counter(scan_s, benchmark::Counter::kAvgIterations);
}
BENCHMARK_CAPTURE(BM_ReadBag, mcap_zstd, std::string("mcap_zstd"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_ReadBag, mcap_lz4, std::string("mcap_lz4"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_ReadBag, mcap_none, std::string("mcap_none"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_ReadBag, ros1, std::string("ros1"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_ReadBag, ros2, std::string("ros2"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

}  // namespace
}  // namespace x2car
