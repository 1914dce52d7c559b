// x2car simulate: one procedural drive with its sensors' data and ground truth (x2car/sim).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/number_checks.hpp"
#include "apps/x2car/output_paths.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/simulation_config.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/pose_file.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/simulation.hpp"

namespace x2car::cli {
namespace {

// What the command line gave; an option not given leaves the library's default
// (sim::SimulationOptions) or the --config file's value.
struct SimulateArguments {
  std::optional<std::string> scenario;
  std::optional<double> duration_s;
  std::optional<std::uint64_t> seed;
  std::string out_dir;
  std::optional<std::vector<std::string>> sensors;
  std::string mounting_path;
  std::string ins_preset = "rtk";
  std::optional<std::string> lidar_format;
  std::optional<int> lidar_beams;
  std::string radar_format = "conti";
  std::optional<std::string> camera_format;
  std::string trajectory_path;
  std::string trajectory_format = "auto";
  double trajectory_rate_hz = 10.0;
  std::string config_path;
  bool print_config = false;
};

// KITTI (12 numbers a line) or TUM (8), from the first line that is not blank or a comment.
std::string trajectory_format_of(const std::string& path) {
  // Named: the lines view this text, and a temporary in the range-for would die before the body.
  const std::string text = io::read_text_file(path);
  for (const io::TextLine& line : io::split_lines(text)) {
    const std::size_t fields = io::split_fields(line.text).size();
    if (fields == 12) return "kitti";
    if (fields == 8) return "tum";
    throw InputError(path, line.number, "poses",
                     "expected KITTI poses (12 numbers a line) or TUM poses (t x y z qx qy qz qw)");
  }
  throw InputError(path, "no poses");
}

// The recorded path in a z-up world. KITTI times come from times.txt beside the poses when there
// is one, else from the rate.
std::vector<StampedPose> read_recorded_path(const SimulateArguments& arguments) {
  const std::string& path = arguments.trajectory_path;
  const std::string format = arguments.trajectory_format == "auto" ? trajectory_format_of(path)
                                                                   : arguments.trajectory_format;
  if (format == "tum") return io::read_tum_poses(path);
  io::KittiPoseOptions options;
  options.period = 1.0 / arguments.trajectory_rate_hz;
  const auto times = std::filesystem::path(path).parent_path() / "times.txt";
  if (std::filesystem::exists(times)) options.times_file = times;
  return sim::kitti_poses_to_z_up(io::read_kitti_poses(path, options));
}

sim::SimulationOptions simulation_options(const SimulateArguments& arguments) {
  sim::SimulationOptions options;
  if (arguments.scenario) options.scenario = sim::scenario_from_string(*arguments.scenario);
  if (arguments.duration_s) options.duration_s = *arguments.duration_s;
  if (arguments.seed) options.seed = *arguments.seed;
  if (arguments.sensors) options.sensors = *arguments.sensors;
  options.ins = arguments.ins_preset == "sps" ? sim::InsOptions::sps() : sim::InsOptions::rtk();
  if (arguments.lidar_format) {
    options.lidar_format = sim::lidar_file_format_from_string(*arguments.lidar_format);
  }
  options.radar_layout = io::radar_layout_from_string(arguments.radar_format);
  // The Delphi layout is an ESR's: its rate, field of view and 64 track ids.
  options.radar = options.radar_layout == io::RadarLayout::kDelphi
                      ? sim::RadarOptions::delphi_esr()
                      : sim::RadarOptions::conti_ars408();
  // Precedence: the presets above are the base that --config changes; an option given on the
  // command line wins over the file.
  if (!arguments.config_path.empty()) apply_simulation_config(arguments.config_path, options);
  if (arguments.lidar_beams) options.lidar.beams = *arguments.lidar_beams;
  if (arguments.camera_format) {
    options.camera_render.format = sim::camera_image_format_from_string(*arguments.camera_format);
  }
  if (!arguments.mounting_path.empty()) {
    options.mountings = io::read_mountings(arguments.mounting_path);
  }
  if (!arguments.trajectory_path.empty()) {
    options.recorded_path = read_recorded_path(arguments);
    options.recorded_path_file = arguments.trajectory_path;  // errors in the drive name it
    // The recording's length unless --duration cuts it.
    if (!arguments.duration_s) options.duration_s = std::numeric_limits<double>::max();
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
  if (simulation.camera) {
    const core::CameraIntrinsics& camera = *simulation.camera;
    const sim::CameraRenderOptions& render = simulation.camera_output->options;
    std::cout << fmt::format(
        "  camera: {}x{}, fx {:g} fy {:g} cx {:g} cy {:g}, distortion {}; {} frames at {:g} Hz "
        "({})\n",
        camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy,
        core::to_string(camera.distortion_model),
        static_cast<std::size_t>(std::floor(truth.duration_s * render.rate_hz + 1e-9)),
        render.rate_hz, sim::to_string(render.format));
  }
  for (const auto& [sensor, scans] : simulation.radars) {
    std::size_t detections = 0;
    std::size_t moving = 0;
    for (const sim::RadarScan& scan : scans) {
      detections += scan.detections.size();
      for (const auto& detection : scan.detections) moving += detection.is_moving ? 1 : 0;
    }
    std::cout << fmt::format(
        "  {}: {} scans ({}), {} detections, {:.0f} % on moving sources\n", sensor, scans.size(),
        io::to_string(simulation.radar_layout), detections,
        detections == 0 ? 0.0
                        : 100.0 * static_cast<double>(moving) / static_cast<double>(detections));
  }
  std::cout << "  true mountings (vehicle_from_sensor; x y z [m], roll pitch yaw [deg]):\n";
  std::size_t width = 7;
  for (const auto& [sensor, mounting] : truth.vehicle_from_sensor) {
    width = std::max(width, sensor.size());
  }
  for (const auto& [sensor, mounting] : truth.vehicle_from_sensor) {
    std::cout << fmt::format("    {:<{}} {:7.3f} {:7.3f} {:7.3f}   {:8.4f} {:8.4f} {:8.4f}\n",
                             sensor, width, mounting.translation.x(), mounting.translation.y(),
                             mounting.translation.z(), deg_from_rad(mounting.rotation.roll),
                             deg_from_rad(mounting.rotation.pitch),
                             deg_from_rad(mounting.rotation.yaw));
  }
}

int run_simulate(const SimulateArguments& arguments) {
  const sim::SimulationOptions options = simulation_options(arguments);
  if (arguments.print_config) {
    std::cout << format_simulation_config(options);
    return kExitOk;
  }
  if (arguments.out_dir.empty()) {
    throw std::invalid_argument("simulate: --out DIR is required (the folder to write)");
  }
  const NamedPath inputs[] = {{"--trajectory", arguments.trajectory_path},
                              {"--config", arguments.config_path},
                              {"--mounting", arguments.mounting_path}};
  check_output_folder({"--out", arguments.out_dir}, inputs);
  const auto start = std::chrono::steady_clock::now();
  const sim::Simulation simulation = sim::simulate(options);
  ProgressBar progress("lidar sweeps", spdlog::should_log(spdlog::level::info));
  ProgressBar frames("camera frames", spdlog::should_log(spdlog::level::info));
  // The LiDAR is written first: its bar ends before the camera's starts.
  sim::write_simulation(simulation, arguments.out_dir, progress.callback(),
                        [&](std::size_t done, std::size_t total) {
                          progress.finish();
                          frames.update(done, total);
                        });
  progress.finish();
  frames.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_summary(simulation, arguments.out_dir, seconds);
  return kExitOk;
}

}  // namespace

RunCommand setup_simulate_command(CLI::App& command) {
  auto arguments = std::make_shared<SimulateArguments>();
  const sim::SimulationOptions defaults;
  command.add_option("--scenario", arguments->scenario, "Kind of drive")
      ->type_name("NAME")
      ->check(CLI::IsMember(sim::scenario_names()))
      ->default_str(sim::to_string(defaults.scenario));
  command.add_option("--duration", arguments->duration_s, "Seconds of driving")
      ->type_name("SECONDS")
      ->check(positive_number())
      ->default_str(fmt::format("{:g}", defaults.duration_s));
  // Read as text: CLI11 would wrap "-1" to 18446744073709551615.
  command.add_option("--seed", arguments->seed, "Seed of every random draw (0 or more)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            if (text.empty() || !std::all_of(text.begin(), text.end(), ::isdigit)) {
              return "the seed must be a whole number 0 or more, got " + text;
            }
            return {};
          },
          "UINT"))
      ->default_str(std::to_string(defaults.seed));
  // Required unless --print-config (checked when it runs).
  command.add_option("--out", arguments->out_dir, "Folder to write (created if needed; required)")
      ->type_name("DIR");
  command
      .add_option("--sensors", arguments->sensors,
                  "Sensors to simulate, comma-separated; radar is a front radar, "
                  "radar_front, radar_left, radar_rear, ... several radars on one car, each "
                  "written to its own folder")
      ->type_name("LIST")
      ->delimiter(',')
      ->check(CLI::IsMember(sim::simulated_sensor_names()))
      ->default_str(fmt::format("{}", fmt::join(defaults.sensors, ",")));
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
      ->check(CLI::IsMember(sim::lidar_file_format_names()))
      ->default_str(sim::to_string(defaults.lidar_format));
  command
      .add_option("--lidar-beams", arguments->lidar_beams,
                  "LiDAR beam table: 32 (OS1-32-like), 64 (HDL-64-like) or 128 (Pandar128-like)")
      ->type_name("N")
      ->check(CLI::IsMember({32, 64, 128}))
      ->default_str(std::to_string(defaults.lidar.beams));
  command
      .add_option("--radar-format", arguments->radar_format,
                  "Radar as conti (ARS408-like scan files), delphi (ESR-like scan files, 20 Hz) or "
                  "generic (detections.csv)")
      ->type_name("NAME")
      ->check(CLI::IsMember({"conti", "delphi", "generic"}))
      ->capture_default_str();
  command
      .add_option("--camera-format", arguments->camera_format,
                  "Camera images as png (lossless) or jpg (camera.jpeg_quality in --config)")
      ->type_name("NAME")
      ->check(CLI::IsMember(sim::camera_image_format_names()))
      ->default_str(sim::to_string(defaults.camera_render.format));
  command
      .add_option("--trajectory", arguments->trajectory_path,
                  "Drive this recorded path (KITTI or TUM poses) instead of a generated route; "
                  "the drive lasts the recording unless --duration cuts it")
      ->type_name("FILE")
      ->check(CLI::ExistingFile);
  command
      .add_option("--trajectory-format", arguments->trajectory_format,
                  "kitti (12 numbers a line, camera poses: y down, z forward), tum "
                  "(t x y z qx qy qz qw, z up) or auto (by the number of fields)")
      ->type_name("NAME")
      ->check(CLI::IsMember({"auto", "kitti", "tum"}))
      ->capture_default_str();
  command
      .add_option("--trajectory-rate", arguments->trajectory_rate_hz,
                  "Pose rate of a KITTI file without times.txt beside it [Hz]")
      ->type_name("HZ")
      ->check(positive_number())
      ->capture_default_str();
  command
      .add_option("--config", arguments->config_path,
                  "YAML file setting the simulator's parameters (noise, rates, beams, radar, "
                  "vehicle, route, world, camera; docs/simulator.md); options given here win")
      ->type_name("FILE")
      ->check(CLI::ExistingFile);
  command.add_flag("--print-config", arguments->print_config,
                   "Print every parameter (after presets, --config and options) as a --config "
                   "file and exit");
  command.footer(
      "Writes DIR/ground_truth.yaml (every sensor's true vehicle_from_<sensor>), "
      "DIR/trajectory.csv\n"
      "(the car's true motion at 100 Hz) and each sensor's data (DIR/ins/novatel_enu.csv and\n"
      "DIR/ins/ins.csv; DIR/lidar/<start seconds>.pcd, one per sweep; DIR/radar/, one file per\n"
      "scan, and DIR/radar_truth.csv, or DIR/radar_left/ and DIR/radar_left_truth.csv ... for\n"
      "named radars; DIR/camera/intrinsics.yaml (ROS camera_info), "
      "DIR/camera/calib_cam_to_cam.txt\n"
      "(KITTI, camera 02), DIR/camera/images/NNNNNNNNNN.png (one per frame),\n"
      "DIR/camera/timestamps.txt and DIR/camera/labels.csv); see\n"
      "docs/simulator.md and docs/formats.md. Same arguments, same bytes.\n"
      "\n"
      "Example:\n"
      "  x2car simulate --scenario urban --duration 120 --seed 3 --out /tmp/drive\n"
      "  x2car simulate --duration 60 --sensors ins,lidar --lidar-beams 32 --out /tmp/lidar\n"
      "  x2car simulate --duration 60 --sensors ins,radar --radar-format delphi --out /tmp/radar\n"
      "  x2car simulate --duration 60 --sensors ins,camera --camera-format jpg --out /tmp/camera\n"
      "  x2car simulate --duration 60 --sensors ins,radar_front,radar_left,radar_rear --out "
      "/tmp/car\n"
      "  x2car simulate --print-config > sim.yaml   # edit, then: --config sim.yaml");
  return [arguments] { return run_simulate(*arguments); };
}

}  // namespace x2car::cli
