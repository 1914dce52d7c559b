#include "x2car/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/io/ins_csv.hpp"
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

constexpr const char* kTrajectoryFile = "trajectory.csv";

// Where each sensor sits on a car, as ranges of its lever arm in V [m] (origin on the road under
// the rear axle).
struct LeverArmRange {
  double x_min, x_max, y_min, y_max, z_min, z_max;
};

LeverArmRange lever_arm_range(const std::string& sensor) {
  if (sensor == "ins") return {0.0, 1.5, -0.3, 0.3, 0.8, 1.4};     // centre console to boot
  if (sensor == "lidar") return {0.8, 1.8, -0.2, 0.2, 1.5, 2.2};   // roof
  if (sensor == "radar") return {3.4, 3.9, -0.2, 0.2, 0.4, 0.7};   // front bumper
  if (sensor == "camera") return {1.5, 2.0, -0.2, 0.2, 1.2, 1.5};  // behind the windscreen
  throw std::invalid_argument("no mounting model for sensor '" + sensor + "'");
}

io::TrajectoryRow trajectory_row(const VehicleState& state) {
  return {state.time,     state.world_from_vehicle, state.velocity_enu, state.speed,
          state.yaw_rate, state.path_curvature,     state.straight};
}

}  // namespace

std::vector<std::string> simulated_sensor_names() { return {"ins", "lidar"}; }

void SimulationOptions::Check() const {
  if (!(duration_s > 0.0) || !std::isfinite(duration_s)) {
    throw std::invalid_argument("simulation: duration must be a positive number of seconds");
  }
  const std::vector<std::string> known = simulated_sensor_names();
  if (sensors.empty()) throw std::invalid_argument("simulation: no sensors to simulate");
  for (const auto& sensor : sensors) {
    if (std::find(known.begin(), known.end(), sensor) == known.end()) {
      throw std::invalid_argument(
          "simulation: sensor '" + sensor +
          "' is not simulated; the simulated sensors are: " + io::join(known));
    }
  }
  route.Check();
  motion.Check();
  ins.Check();
  world.Check();
  lidar.Check();
}

io::SensorMounting draw_mounting(const std::string& sensor, Random& random) {
  const LeverArmRange arm = lever_arm_range(sensor);
  io::SensorMounting mounting;
  mounting.translation = {random.uniform(arm.x_min, arm.x_max),
                          random.uniform(arm.y_min, arm.y_max),
                          random.uniform(arm.z_min, arm.z_max)};
  mounting.rotation.roll = rad_from_deg(random.uniform(-3.0, 3.0));
  mounting.rotation.pitch = rad_from_deg(random.uniform(-3.0, 3.0));
  mounting.rotation.yaw = rad_from_deg(random.uniform(-5.0, 5.0));
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

  // Every sensor's mounting is drawn, in a fixed order, whether or not it is replaced, so that a
  // --mounting file for one sensor leaves the others as they were.
  Random mounting_random(Random::derive_seed(options.seed, kMountingStream));
  for (const auto& sensor : options.sensors) {
    io::SensorMounting mounting = draw_mounting(sensor, mounting_random);
    if (const auto given = options.mountings.find(sensor); given != options.mountings.end()) {
      mounting = given->second;
    }
    truth.vehicle_from_sensor[sensor] = mounting;
  }

  const double length = route_length_for(options.scenario, options.duration_s, options.motion);
  const Route route = generate_route(options.scenario, length, options.seed, options.route);
  simulation.states =
      simulate_vehicle_motion(route, options.scenario, options.duration_s, options.motion,
                              Random::derive_seed(options.seed, kMotionStream));

  if (truth.vehicle_from_sensor.contains("ins")) {
    simulation.ins =
        simulate_ins(simulation.states, truth.vehicle_from_sensor.at("ins").vehicle_from_sensor(),
                     options.ins, Random::derive_seed(options.seed, kInsNoiseStream));
  }
  if (truth.vehicle_from_sensor.contains("lidar")) {
    WorldOptions world = options.world;
    world.road.highway_lanes = options.route.plan.highway.lanes;  // the lanes the route changes
    world.road.lane_width_m = options.route.plan.highway.lane_width_m;
    simulation.world = generate_world(route, options.scenario, simulation.states, world,
                                      Random::derive_seed(options.seed, kWorldStream));
    simulation.lidar = LidarOutput{options.lidar, options.lidar_format,
                                   Random::derive_seed(options.seed, kLidarNoiseStream)};
  }
  return simulation;
}

void write_simulation(const Simulation& simulation, const std::filesystem::path& out_dir) {
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) throw InputError(out_dir.string(), "cannot create the folder: " + error.message());
  io::write_ground_truth(out_dir / "ground_truth.yaml", simulation.truth);

  std::vector<io::TrajectoryRow> rows;
  rows.reserve(simulation.states.size());
  for (const auto& state : simulation.states) rows.push_back(trajectory_row(state));
  io::write_trajectory_csv(out_dir / simulation.truth.trajectory_file, rows);

  if (!simulation.ins.empty()) {
    std::filesystem::create_directories(out_dir / "ins", error);
    if (error) throw InputError((out_dir / "ins").string(), "cannot create: " + error.message());
    io::write_novatel_enu(out_dir / "ins" / "novatel_enu.csv", simulation.ins,
                          simulation.start_unix_time);
    io::write_ins_csv(out_dir / "ins" / "ins.csv", simulation.ins);
  }
  if (simulation.lidar) {
    write_simulated_lidar(simulation.world, simulation.states,
                          simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor(),
                          *simulation.lidar, out_dir / "lidar");
  }
}

}  // namespace x2car::sim
