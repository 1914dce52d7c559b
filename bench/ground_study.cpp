// Study of per-sweep ground fits (lidar/ground.hpp) on simulated drives: what they measure against
// the simulator's truth, and what biases them. Not a Google Benchmark: it writes one CSV row per
// (sweep, fit variant) for analysis (scripts or a spreadsheet), and prints the time per fit.
//
//   x2car_ground_study [--seeds 1,2,3] [--beams 32,64,128] [--stride 5] [--duration 60]
//                      [--scenario urban] [--out ground_study.csv]
//
// Columns: the drive (seed, beams, sweep, t_mid), the car's true motion at the sweep's middle
// (speed, yaw rate, lateral and longitudinal acceleration, pitch rate in V, the road's grade,
// crossfall and grade rate under the car), the body's roll and pitch on its suspension (the
// rotation from the road's frame to V), the truth (mounting roll/pitch/height of
// vehicle_from_lidar, and the instantaneous road plane at the rear axle seen from the LiDAR:
// inst_roll/inst_pitch/inst_height), and each variant's fit (roll, pitch, height, inliers, rms,
// ms). Angles in degrees, lengths in metres.
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "x2car/lidar/ground.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car {
namespace {

struct Variant {
  std::string name;
  lidar::GroundOptions options;
};

std::vector<Variant> variants() {
  std::vector<Variant> list;
  const auto add = [&](std::string name, double max_range, double max_lateral) {
    lidar::GroundOptions options;
    options.max_range_m = max_range;
    options.max_lateral_m = max_lateral;
    list.push_back({std::move(name), options});
  };
  add("r10_l3", 10.0, 3.0);
  add("r15_l3", 15.0, 3.0);
  add("r20_l3", 20.0, 3.0);
  add("r30_l3", 30.0, 3.0);
  add("r15_l2", 15.0, 2.0);
  add("r20_l4", 20.0, 4.0);
  return list;
}

std::vector<long> parse_list(const std::string& text) {
  std::vector<long> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) values.push_back(std::stol(item));
  return values;
}

// Interpolated state fields at `time` (linear between the 100 Hz states).
sim::VehicleState state_at(const sim::VehicleStates& states, double time) {
  std::size_t i = 0;
  while (i + 2 < states.size() && states[i + 1].time <= time) ++i;
  const sim::VehicleState& a = states[i];
  const sim::VehicleState& b = states[i + 1];
  const double w = std::clamp((time - a.time) / (b.time - a.time), 0.0, 1.0);
  sim::VehicleState s = a;
  const auto mix = [w](double x, double y) { return x + w * (y - x); };
  s.time = time;
  s.speed = mix(a.speed, b.speed);
  s.yaw_rate = mix(a.yaw_rate, b.yaw_rate);
  s.lateral_acceleration = mix(a.lateral_acceleration, b.lateral_acceleration);
  s.longitudinal_acceleration = mix(a.longitudinal_acceleration, b.longitudinal_acceleration);
  s.arc_length = mix(a.arc_length, b.arc_length);
  s.angular_velocity_vehicle =
      a.angular_velocity_vehicle + w * (b.angular_velocity_vehicle - a.angular_velocity_vehicle);
  s.world_from_vehicle = sim::world_from_vehicle_at(states, time);
  return s;
}

void run_drive(std::uint64_t seed, int beams, std::size_t stride, double duration,
               sim::Scenario scenario, std::ostream& csv, double& total_ms, std::size_t& fits) {
  const sim::Simulation simulation =
      sim::simulate(sim::testing::simulated_lidar_drive(scenario, duration, beams, seed));
  const Eigen::Isometry3d vehicle_from_lidar =
      simulation.truth.vehicle_from_sensor.at("lidar").vehicle_from_sensor();
  const sim::WorldScene scene(simulation.world);
  const sim::LidarSimulator lidar(scene, simulation.states, vehicle_from_lidar,
                                  simulation.lidar->options, simulation.lidar->seed);
  const EulerAngles mount = euler_from_rotation(vehicle_from_lidar.linear());
  const double mount_height = vehicle_from_lidar.translation().z();
  const std::vector<Variant> list = variants();
  const std::size_t count = (lidar.sweep_count() + stride - 1) / stride;
  std::vector<std::string> rows(count);
  std::vector<double> ms(count, 0.0);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
    const std::size_t index = k * stride;
    const sim::LidarSweep sweep = lidar.sweep(index);
    const double t_mid = lidar.sweep_start_time(index) + 0.5 / lidar.options().rate_hz;
    const sim::VehicleState state = state_at(simulation.states, t_mid);
    const sim::VehicleState before = state_at(simulation.states, std::max(0.0, t_mid - 0.3));
    const sim::RoadStation station = simulation.world.road.station_at(state.arc_length);
    const sim::RoadStation ahead = simulation.world.road.station_at(state.arc_length + 1.0);
    const Eigen::Matrix3d world_from_road = station.surface_rotation();
    const Eigen::Vector3d road_normal = world_from_road.col(2);
    // Body on the suspension: V relative to the road's frame at the car (same heading).
    const Eigen::Matrix3d road_from_vehicle =
        world_from_road.transpose() * state.world_from_vehicle.linear();
    const EulerAngles body = euler_from_rotation(road_from_vehicle);
    const Eigen::Isometry3d world_from_lidar = lidar.world_from_lidar(t_mid);
    const Eigen::Vector3d normal_in_lidar = world_from_lidar.linear().transpose() * road_normal;
    const double inst_height =
        road_normal.dot(world_from_lidar.translation() - state.world_from_vehicle.translation());
    std::string row;
    for (const Variant& variant : list) {
      const auto start = std::chrono::steady_clock::now();
      const lidar::GroundFit fit = lidar::fit_ground(sweep.cloud, variant.options, index);
      const double fit_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      if (variant.name == "r20_l3") ms[k] = fit_ms;
      double roll = NAN, pitch = NAN, height = NAN, rms = NAN;
      std::size_t inliers = 0;
      if (fit.plane) {
        roll = deg_from_rad(lidar::roll_from_ground(fit.plane->normal_in_lidar));
        pitch = deg_from_rad(lidar::pitch_from_ground(fit.plane->normal_in_lidar));
        height = fit.plane->height_m;
        rms = fit.plane->rms_m;
        inliers = fit.plane->inliers;
      }
      row += fmt::format(
          "{},{},{},{:.3f},{:.4f},{:.5f},{:.4f},{:.4f},{:.6f},{:.6f},{:.6f},{:.7f},{:.5f},{:.5f},"
          "{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{},{:.5f},{:.5f},{:.5f},{},{:.4f},{:."
          "3f},{},{:.4f},{:.4f}\n",
          seed, beams, index, t_mid, state.speed, state.yaw_rate, state.lateral_acceleration,
          state.longitudinal_acceleration, state.angular_velocity_vehicle.y(), station.grade,
          station.crossfall, ahead.grade - station.grade, deg_from_rad(body.roll),
          deg_from_rad(body.pitch), deg_from_rad(mount.roll), deg_from_rad(mount.pitch),
          mount_height, deg_from_rad(lidar::roll_from_ground(normal_in_lidar)),
          deg_from_rad(lidar::pitch_from_ground(normal_in_lidar)), inst_height,
          vehicle_from_lidar.translation().x(), variant.name, roll, pitch, height, inliers, rms,
          fit_ms, sweep.cloud.points.size(), before.lateral_acceleration,
          before.longitudinal_acceleration);
    }
    rows[k] = std::move(row);
  });
  for (std::size_t k = 0; k < count; ++k) {
    csv << rows[k];
    total_ms += ms[k];
    ++fits;
  }
}

}  // namespace
}  // namespace x2car

int main(int argc, char** argv) {
  std::vector<long> seeds = {1, 2, 3, 4, 5}, beams = {64};
  std::size_t stride = 5;
  double duration = 60.0;
  std::string scenario = "urban", out = "ground_study.csv";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--seeds")
      seeds = x2car::parse_list(value);
    else if (key == "--beams")
      beams = x2car::parse_list(value);
    else if (key == "--stride")
      stride = std::stoul(value);
    else if (key == "--duration")
      duration = std::stod(value);
    else if (key == "--scenario")
      scenario = value;
    else if (key == "--out")
      out = value;
    else {
      std::cerr << "unknown option " << key << "\n";
      return 2;
    }
  }
  std::ofstream csv(out);
  csv << "seed,beams,sweep,t_mid,speed,yaw_rate,lat_acc,long_acc,pitch_rate,grade,crossfall,"
         "grade_rate,body_roll,body_pitch,mount_roll,mount_pitch,mount_height,inst_roll,"
         "inst_pitch,inst_height,lever_x,variant,roll,pitch,height,inliers,rms,ms,points,lat_acc_"
         "before,long_acc_before\n";
  for (const long b : beams) {
    double total_ms = 0.0;
    std::size_t fits = 0;
    for (const long seed : seeds) {
      x2car::run_drive(static_cast<std::uint64_t>(seed), static_cast<int>(b), stride, duration,
                       x2car::sim::scenario_from_string(scenario), csv, total_ms, fits);
      std::cerr << fmt::format("beams {} seed {} done\n", b, seed);
    }
    std::cout << fmt::format("{} beams: ground fit (default options) {:.2f} ms per sweep\n", b,
                             total_ms / static_cast<double>(fits));
  }
  return 0;
}
