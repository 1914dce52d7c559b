#include "x2car/sim/simulation.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/kitti_calib_cam.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

// Independent random streams of one seed (Random::derive_seed), so that adding draws to one part
// of the simulation does not change another's output.
constexpr std::uint64_t kMountingStream = 101;
constexpr std::uint64_t kInsNoiseStream = 201;
constexpr std::uint64_t kMotionStream = 301;
constexpr std::uint64_t kWorldStream = 401;
constexpr std::uint64_t kLidarNoiseStream = 501;
constexpr std::uint64_t kRadarMountingStream = 102;
constexpr std::uint64_t kCameraMountingStream = 103;
constexpr std::uint64_t kRadarNoiseStream = 601;
constexpr std::uint64_t kCameraNoiseStream = 701;
// The named radars' (radar_positions, in table order): one stream each, + index.
constexpr std::uint64_t kNamedRadarMountingStream = 110;
constexpr std::uint64_t kNamedRadarNoiseStream = 610;

constexpr const char* kTrajectoryFile = "trajectory.csv";

// Where each sensor sits on a car: ranges of its lever arm in V [m] (origin on the road under the
// rear axle), the largest roll and pitch [deg] it is fitted with, and its nominal yaw [deg].
struct MountingRange {
  double x_min, x_max, y_min, y_max, z_min, z_max, max_tilt_deg;
  double nominal_yaw_deg = 0.0;
};

// The named radars on a car of 4.7 m (front bumper 3.8 m ahead of the rear axle, rear bumper 0.9 m
// behind it, 1.8 m wide); the right-hand ones mirror the left-hand ones.
struct NamedRadar {
  const char* name;
  MountingRange range;
};
constexpr double kRadarTilt = 1.0;  // [deg]
constexpr std::array<NamedRadar, 8> kNamedRadars{{
    {"front", {3.5, 3.9, -0.2, 0.2, 0.4, 0.6, kRadarTilt, 0.0}},
    {"front_left", {3.3, 3.6, 0.6, 0.8, 0.4, 0.6, kRadarTilt, 25.0}},
    {"front_right", {3.3, 3.6, -0.8, -0.6, 0.4, 0.6, kRadarTilt, -25.0}},
    {"left", {3.0, 3.4, 0.8, 0.9, 0.4, 0.6, kRadarTilt, 90.0}},
    {"right", {3.0, 3.4, -0.9, -0.8, 0.4, 0.6, kRadarTilt, -90.0}},
    {"rear", {-1.1, -0.8, -0.2, 0.2, 0.4, 0.6, kRadarTilt, 180.0}},
    {"rear_left", {-1.0, -0.6, 0.6, 0.8, 0.4, 0.6, kRadarTilt, 135.0}},
    {"rear_right", {-1.0, -0.6, -0.8, -0.6, 0.4, 0.6, kRadarTilt, -135.0}},
}};
constexpr std::string_view kNamedRadarPrefix = "radar_";

MountingRange mounting_range(const std::string& sensor) {
  if (sensor == "ins") return {0.0, 1.5, -0.3, 0.3, 0.8, 1.4, 3.0};     // centre console to boot
  if (sensor == "lidar") return {0.8, 1.8, -0.2, 0.2, 1.5, 2.2, 3.0};   // roof
  if (sensor == "radar") return {3.5, 3.9, -0.2, 0.2, 0.4, 0.6, 1.0};   // front bumper
  if (sensor == "camera") return {1.5, 2.0, -0.2, 0.2, 1.3, 1.5, 3.0};  // behind the windscreen
  for (const NamedRadar& radar : kNamedRadars) {
    if (sensor == std::string(kNamedRadarPrefix) + radar.name) return radar.range;
  }
  throw std::invalid_argument("no mounting model for sensor '" + sensor + "'");
}

// The drawn mounting of every simulated sensor. The GNSS/INS and the LiDAR share the first stream,
// drawn in that order whichever of them is simulated; every later sensor has a stream of its own,
// so that adding a sensor changes no other's mounting.
io::SensorMountings draw_mountings(std::uint64_t seed) {
  io::SensorMountings drawn;
  Random shared(Random::derive_seed(seed, kMountingStream));
  drawn["ins"] = draw_mounting("ins", shared);
  drawn["lidar"] = draw_mounting("lidar", shared);
  Random radar(Random::derive_seed(seed, kRadarMountingStream));
  drawn["radar"] = draw_mounting("radar", radar);
  Random camera(Random::derive_seed(seed, kCameraMountingStream));
  drawn["camera"] = draw_mounting("camera", camera);
  for (std::size_t i = 0; i < kNamedRadars.size(); ++i) {
    Random named(Random::derive_seed(seed, kNamedRadarMountingStream + i));
    const std::string sensor = std::string(kNamedRadarPrefix) + kNamedRadars[i].name;
    drawn[sensor] = draw_mounting(sensor, named);
  }
  return drawn;
}

// The radar noise stream of a radar sensor: "radar" keeps its own, the named ones follow the
// table.
std::uint64_t radar_noise_stream(const std::string& sensor) {
  for (std::size_t i = 0; i < kNamedRadars.size(); ++i) {
    if (sensor == std::string(kNamedRadarPrefix) + kNamedRadars[i].name) {
      return kNamedRadarNoiseStream + i;
    }
  }
  return kRadarNoiseStream;
}

constexpr std::array<EnumName<RadarSource>, 3> kRadarSourceNames{{
    {RadarSource::kTarget, "target"},
    {RadarSource::kGhost, "ghost"},
    {RadarSource::kClutter, "clutter"},
}};

const char* to_string(RadarSource source) { return enum_to_string(kRadarSourceNames, source); }

void create_folder(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder.string(), "cannot create the folder: " + error.message());
}

void empty_folder(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::remove_all(folder, error);
  if (error) throw InputError(folder.string(), "cannot empty: " + error.message());
  create_folder(folder);
}

io::TrajectoryRow trajectory_row(const VehicleState& state) {
  return {state.time,     state.world_from_vehicle, state.velocity_enu, state.speed,
          state.yaw_rate, state.path_curvature,     state.straight};
}

// The route and the car's motion on it: a generated drive, or the recorded path's (cut to the
// duration).
Route drive(const SimulationOptions& options, VehicleStates& states) {
  if (options.recorded_path.empty()) {
    const double length = route_length_for(options.scenario, options.duration_s, options.motion);
    Route route = generate_route(options.scenario, length, options.seed, options.route);
    states = simulate_vehicle_motion(route, options.scenario, options.duration_s, options.motion,
                                     Random::derive_seed(options.seed, kMotionStream));
    return route;
  }
  std::vector<StampedPose> poses;
  for (const StampedPose& pose : options.recorded_path) {
    if (pose.time - options.recorded_path.front().time > options.duration_s) break;
    poses.push_back(pose);
  }
  // The options were checked before (SimulationOptions::Check), so what fails here is the
  // recording itself: name its file when there is one.
  try {
    RecordedDrive recorded = fit_recorded_drive(poses, options.recorded);
    states = simulate_recorded_motion(recorded.route, recorded.times, recorded.arc_lengths,
                                      options.motion);
    return std::move(recorded.route);
  } catch (const std::invalid_argument& error) {
    if (options.recorded_path_file.empty()) throw;
    throw InputError(options.recorded_path_file, error.what());
  }
}

}  // namespace

std::vector<std::string> simulated_sensor_names() {
  std::vector<std::string> names = {"ins", "lidar", "radar", "camera"};
  for (const NamedRadar& radar : kNamedRadars) {
    names.push_back(std::string(kNamedRadarPrefix) + radar.name);
  }
  return names;
}

std::vector<RadarPosition> radar_positions() {
  std::vector<RadarPosition> positions;
  for (const NamedRadar& radar : kNamedRadars) {
    positions.push_back({radar.name, radar.range.nominal_yaw_deg});
  }
  return positions;
}

bool is_radar_sensor(const std::string& sensor) {
  if (sensor == "radar") return true;
  return std::any_of(kNamedRadars.begin(), kNamedRadars.end(), [&](const NamedRadar& radar) {
    return sensor == std::string(kNamedRadarPrefix) + radar.name;
  });
}

std::string radar_truth_file(const std::string& sensor) { return sensor + "_truth.csv"; }

void SimulationOptions::Check() const {
  const OptionsCheck check("SimulationOptions");
  check.positive("duration_s", duration_s);
  const std::vector<std::string> known = simulated_sensor_names();
  check.that(!sensors.empty(), "sensors", "must name at least one sensor");
  for (const auto& sensor : sensors) {
    check.that(std::find(known.begin(), known.end(), sensor) != known.end(), "sensors",
               fmt::format("must be among the simulated sensors {} ('{}' is not)", io::join(known),
                           sensor));
  }
  check.that(recorded_path.empty() || scenario != Scenario::kMixed, "scenario",
             "must be straight, urban or highway with a recorded path (one kind of road), "
             "not mixed");
  recorded.Check();
  route.Check();
  motion.Check();
  ins.Check();
  world.Check();
  lidar.Check();
  radar.Check();
  world_radar.Check();
  camera.Check();
  camera_render.Check();
  // The layouts' track id fields: Conti 0-99, Delphi 0-63 (a cluster radar writes none).
  const int max_ids = radar_layout == io::RadarLayout::kDelphi ? 64 : 100;
  check.that(
      radar_layout == io::RadarLayout::kGeneric || !radar.track_ids ||
          radar.track_id_count <= max_ids,
      "radar.track_id_count",
      fmt::format("must be <= {} for the {} radar layout", max_ids, io::to_string(radar_layout)),
      radar.track_id_count);
}

io::SensorMounting draw_mounting(const std::string& sensor, Random& random) {
  const MountingRange arm = mounting_range(sensor);
  io::SensorMounting mounting;
  mounting.translation = {random.uniform(arm.x_min, arm.x_max),
                          random.uniform(arm.y_min, arm.y_max),
                          random.uniform(arm.z_min, arm.z_max)};
  mounting.rotation.roll = rad_from_deg(random.uniform(-arm.max_tilt_deg, arm.max_tilt_deg));
  mounting.rotation.pitch = rad_from_deg(random.uniform(-arm.max_tilt_deg, arm.max_tilt_deg));
  mounting.rotation.yaw = wrap_angle(rad_from_deg(arm.nominal_yaw_deg + random.uniform(-5.0, 5.0)));
  return mounting;
}

Simulation simulate(const SimulationOptions& options) {
  options.Check();
  Simulation simulation;
  simulation.start_unix_time = options.start_unix_time;
  io::GroundTruth& truth = simulation.truth;
  truth.scenario = to_string(options.scenario);
  truth.seed = options.seed;
  truth.duration_s = options.duration_s;
  truth.trajectory_file = kTrajectoryFile;

  // Every sensor's mounting is drawn whether or not it is simulated or replaced, so that a
  // --mounting file for one sensor or another choice of sensors leaves the others as they were.
  const io::SensorMountings drawn = draw_mountings(options.seed);
  for (const auto& sensor : options.sensors) {
    const auto given = options.mountings.find(sensor);
    truth.vehicle_from_sensor[sensor] =
        given != options.mountings.end() ? given->second : drawn.at(sensor);
  }

  const Route route = drive(options, simulation.states);
  truth.duration_s = simulation.states.back().time;

  if (truth.vehicle_from_sensor.contains("ins")) {
    simulation.ins =
        simulate_ins(simulation.states, truth.vehicle_from_sensor.at("ins").vehicle_from_sensor(),
                     options.ins, Random::derive_seed(options.seed, kInsNoiseStream));
  }
  const bool lidar = truth.vehicle_from_sensor.contains("lidar");
  const bool radar = std::any_of(options.sensors.begin(), options.sensors.end(), is_radar_sensor);
  const bool camera = truth.vehicle_from_sensor.contains("camera");
  if (lidar || radar || camera) {  // one world, whichever sensors see it
    WorldOptions world = options.world;
    world.road.highway_lanes = options.route.plan.highway.lanes;  // the lanes the route changes
    world.road.lane_width_m = options.route.plan.highway.lane_width_m;
    simulation.world = generate_world(route, options.scenario, simulation.states, world,
                                      Random::derive_seed(options.seed, kWorldStream));
  }
  if (lidar) {
    simulation.lidar = LidarOutput{options.lidar, options.lidar_format,
                                   Random::derive_seed(options.seed, kLidarNoiseStream)};
  }
  if (radar) {  // one scene, seen by every radar
    const RadarScene scene =
        radar_scene_from_world(simulation.world, simulation.states.front().time,
                               simulation.states.back().time, options.world_radar);
    for (const auto& [sensor, mounting] : truth.vehicle_from_sensor) {
      if (!is_radar_sensor(sensor)) continue;
      simulation.radars[sensor] =
          simulate_radar(simulation.states, mounting.vehicle_from_sensor(), scene, options.radar,
                         Random::derive_seed(options.seed, radar_noise_stream(sensor)));
    }
    simulation.radar_layout = options.radar_layout;
  }
  if (camera) {
    simulation.camera = options.camera.intrinsics;
    simulation.camera_output =
        CameraOutput{options.camera_render, Random::derive_seed(options.seed, kCameraNoiseStream)};
  }
  return simulation;
}

std::string format_radar_truth_csv(std::span<const RadarScan> scans) {
  std::string text = "time,track_id,source,object_id,moving,range,azimuth,range_rate\n";
  for (const RadarScan& scan : scans) {
    for (const SimulatedRadarDetection& d : scan.detections) {
      text += fmt::format(
          "{},{},{},{},{},{}\n", io::format_number(d.measurement.time), d.measurement.track_id,
          to_string(d.source), d.object_id, d.is_moving ? 1 : 0,
          io::format_numbers({d.truth.range, d.truth.azimuth, d.truth.range_rate}, ","));
    }
  }
  return text;
}

namespace {

// KITTI's calib_time form, "09-Jan-2012 13:57:47" (UTC), of the log's time 0.
std::string kitti_calib_time(double unix_time) {
  const auto seconds = static_cast<std::time_t>(std::floor(unix_time));
  return fmt::format("{:%d-%b-%Y %H:%M:%S}", fmt::gmtime(seconds));
}

}  // namespace

void write_simulation(const Simulation& simulation, const std::filesystem::path& out_dir,
                      const SweepProgress& lidar_progress, const FrameProgress& camera_progress) {
  create_folder(out_dir);
  io::write_ground_truth(out_dir / "ground_truth.yaml", simulation.truth);

  std::vector<io::TrajectoryRow> rows;
  rows.reserve(simulation.states.size());
  for (const auto& state : simulation.states) rows.push_back(trajectory_row(state));
  io::write_trajectory_csv(out_dir / simulation.truth.trajectory_file, rows);

  if (!simulation.ins.empty()) {
    create_folder(out_dir / "ins");
    io::write_novatel_enu(out_dir / "ins" / "novatel_enu.csv", simulation.ins,
                          simulation.start_unix_time);
    io::write_ins_csv(out_dir / "ins" / "ins.csv", simulation.ins);
  }
  if (simulation.lidar) {
    write_simulated_lidar(simulation.world, simulation.states,
                          simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor(),
                          *simulation.lidar, out_dir / "lidar", lidar_progress);
  }
  for (const auto& [sensor, scans] : simulation.radars) {
    empty_folder(out_dir / sensor);  // created even when no scan has a detection
    io::write_radar(out_dir / sensor, simulation.radar_layout, radar_measurements(scans),
                    simulation.start_unix_time);
    io::write_text_file(out_dir / radar_truth_file(sensor), format_radar_truth_csv(scans));
  }
  if (simulation.camera) {
    create_folder(out_dir / "camera");
    const std::filesystem::path folder = out_dir / "camera";
    io::write_camera_info_yaml(folder / kCameraIntrinsicsFile, *simulation.camera);
    io::write_kitti_calib_cam(folder / kCameraKittiCalibFile, *simulation.camera, kCameraKittiIndex,
                              kitti_calib_time(simulation.start_unix_time));
    if (simulation.camera_output) {
      write_simulated_camera(
          simulation.world, simulation.states,
          simulation.truth.vehicle_from_sensor.at("camera").vehicle_from_sensor(),
          *simulation.camera, *simulation.camera_output, folder, simulation.start_unix_time,
          camera_progress);
    }
  }
}

}  // namespace x2car::sim
