// x2car simulate: one procedural drive with its sensors' data and ground truth (x2car/sim).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car::cli {
namespace {

struct SimulateArguments {
  std::string scenario = "urban";
  double duration_s = 60.0;
  std::uint64_t seed = 1;
  std::string out_dir;
  std::vector<std::string> sensors = {"ins"};
  std::string mounting_path;
  std::string ins_preset = "rtk";
  std::string lidar_format = "pcd";
  int lidar_beams = 64;
};

sim::SimulationOptions simulation_options(const SimulateArguments& arguments) {
  sim::SimulationOptions options;
  options.scenario = sim::scenario_from_string(arguments.scenario);
  options.duration_s = arguments.duration_s;
  options.seed = arguments.seed;
  options.sensors = arguments.sensors;
  options.ins = arguments.ins_preset == "sps" ? sim::InsOptions::sps() : sim::InsOptions::rtk();
  options.lidar.beams = arguments.lidar_beams;
  options.lidar_format = sim::lidar_file_format_from_string(arguments.lidar_format);
  if (!arguments.mounting_path.empty()) {
    options.mountings = io::read_mountings(arguments.mounting_path);
  }
  return options;
}

void print_summary(const sim::Simulation& simulation, const std::string& out_dir, double seconds) {
  const io::GroundTruth& truth = simulation.truth;
  std::cout << fmt::format("simulated {:g} s of {} driving (seed {}) in {:.2f} s -> {}\n",
                           truth.duration_s, truth.scenario, truth.seed, seconds, out_dir);
  std::cout << fmt::format("  trajectory: {} states; ins: {} samples\n", simulation.states.size(),
                           simulation.ins.size());
  if (simulation.lidar) {
    std::cout << fmt::format("  lidar: {} beams at {:g} Hz ({}); world: {} objects, {} movers\n",
                             simulation.lidar->options.beams, simulation.lidar->options.rate_hz,
                             sim::to_string(simulation.lidar->format),
                             simulation.world.objects.size(), simulation.world.movers.size());
  }
  std::cout << "  true mountings (vehicle_from_sensor; x y z [m], roll pitch yaw [deg]):\n";
  for (const auto& [sensor, mounting] : truth.vehicle_from_sensor) {
    std::cout << fmt::format("    {:<7} {:7.3f} {:7.3f} {:7.3f}   {:8.4f} {:8.4f} {:8.4f}\n",
                             sensor, mounting.translation.x(), mounting.translation.y(),
                             mounting.translation.z(), deg_from_rad(mounting.rotation.roll),
                             deg_from_rad(mounting.rotation.pitch),
                             deg_from_rad(mounting.rotation.yaw));
  }
}

int run_simulate(const SimulateArguments& arguments) {
  const auto start = std::chrono::steady_clock::now();
  const sim::Simulation simulation = sim::simulate(simulation_options(arguments));
  sim::write_simulation(simulation, arguments.out_dir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_summary(simulation, arguments.out_dir, seconds);
  return kExitOk;
}

}  // namespace

RunCommand setup_simulate_command(CLI::App& command) {
  auto arguments = std::make_shared<SimulateArguments>();
  command.add_option("--scenario", arguments->scenario, "Kind of drive")
      ->type_name("NAME")
      ->check(CLI::IsMember({"straight", "urban", "highway", "mixed"}))
      ->capture_default_str();
  command.add_option("--duration", arguments->duration_s, "Seconds of driving")
      ->type_name("SECONDS")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command.add_option("--seed", arguments->seed, "Seed of every random draw")->capture_default_str();
  command.add_option("--out", arguments->out_dir, "Folder to write (created if needed)")
      ->type_name("DIR")
      ->required();
  command.add_option("--sensors", arguments->sensors, "Sensors to simulate, comma-separated")
      ->type_name("LIST")
      ->delimiter(',')
      ->check(CLI::IsMember(sim::simulated_sensor_names()))
      ->capture_default_str();
  command
      .add_option("--mounting", arguments->mounting_path,
                  "YAML with vehicle_from_<sensor> entries (the layout of ground_truth.yaml) "
                  "that replace the drawn mountings")
      ->type_name("FILE");
  command
      .add_option("--ins-preset", arguments->ins_preset,
                  "GNSS/INS accuracy: rtk (~2 cm) or sps (~1 m)")
      ->type_name("NAME")
      ->check(CLI::IsMember({"rtk", "sps"}))
      ->capture_default_str();
  command
      .add_option("--lidar-format", arguments->lidar_format,
                  "LiDAR sweeps as pcd (binary PCD), kitti (velodyne .bin + times.txt) or both")
      ->type_name("NAME")
      ->check(CLI::IsMember({"pcd", "kitti", "both"}))
      ->capture_default_str();
  command
      .add_option("--lidar-beams", arguments->lidar_beams,
                  "LiDAR beam table: 32 (OS1-32-like), 64 (HDL-64-like) or 128 (Pandar128-like)")
      ->type_name("N")
      ->check(CLI::IsMember({32, 64, 128}))
      ->capture_default_str();
  command.footer(
      "Writes DIR/ground_truth.yaml (every sensor's true vehicle_from_<sensor>), "
      "DIR/trajectory.csv\n"
      "(the car's true motion at 100 Hz) and each sensor's data (DIR/ins/novatel_enu.csv and\n"
      "DIR/ins/ins.csv; DIR/lidar/<start seconds>.pcd, one per sweep); see docs/simulator.md and\n"
      "docs/formats.md. Same arguments, same bytes.\n"
      "\n"
      "Example:\n"
      "  x2car simulate --scenario urban --duration 120 --seed 3 --out /tmp/drive\n"
      "  x2car simulate --duration 60 --sensors ins,lidar --lidar-beams 32 --out /tmp/lidar");
  return [arguments] { return run_simulate(*arguments); };
}

}  // namespace x2car::cli
