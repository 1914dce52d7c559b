#include "x2car/sim/simulation.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/kitti_calib_cam.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/pose_file.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::sim {
namespace {

SimulationOptions short_urban_drive(std::uint64_t seed) {
  return testing::simulated_drive(Scenario::kUrban, 40.0, seed);
}

std::filesystem::path temp_folder(const std::string& name) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(path);
  return path;
}

// Mean of (reported device yaw - true path heading) over the straight samples [rad]. On a
// straight the car's x axis follows the path, so this is the mounting yaw plus noise and bias.
double mean_yaw_offset_on_straights(const Simulation& simulation) {
  std::vector<double> offsets;
  for (std::size_t i = 0; i < simulation.ins.size(); ++i) {
    const VehicleState& state = simulation.states[i];
    if (!state.straight || state.speed < 3.0) continue;
    offsets.push_back(angle_difference(simulation.ins[i].attitude.yaw, state.heading_enu));
  }
  EXPECT_GT(offsets.size(), 500u);
  return weighted_mean(offsets);
}

TEST(Simulation, SameArgumentsWriteTheSameBytes) {
  const auto first = temp_folder("simulation_a");
  const auto second = temp_folder("simulation_b");
  write_simulation(simulate(short_urban_drive(7)), first);
  write_simulation(simulate(short_urban_drive(7)), second);
  for (const char* file :
       {"ground_truth.yaml", "trajectory.csv", "ins/novatel_enu.csv", "ins/ins.csv"}) {
    EXPECT_EQ(io::read_text_file(first / file), io::read_text_file(second / file)) << file;
  }
  const auto other_seed = temp_folder("simulation_c");
  write_simulation(simulate(short_urban_drive(8)), other_seed);
  EXPECT_NE(io::read_text_file(first / "ins/ins.csv"),
            io::read_text_file(other_seed / "ins/ins.csv"));
}

TEST(Simulation, GroundTruthFileRoundTripsAndNamesTheTrajectory) {
  const auto folder = temp_folder("simulation_truth");
  const Simulation simulation = simulate(short_urban_drive(3));
  write_simulation(simulation, folder);
  const io::GroundTruth truth = io::read_ground_truth(folder / "ground_truth.yaml");
  EXPECT_EQ(truth.scenario, "urban");
  EXPECT_EQ(truth.seed, 3u);
  ASSERT_TRUE(truth.vehicle_from_sensor.contains("ins"));
  const io::SensorMounting& written = truth.vehicle_from_sensor.at("ins");
  const io::SensorMounting& drawn = simulation.truth.vehicle_from_sensor.at("ins");
  EXPECT_EQ(written.rotation.yaw, drawn.rotation.yaw);
  EXPECT_EQ(written.translation, drawn.translation);
  const auto rows = io::read_trajectory_csv(folder / truth.trajectory_file);
  EXPECT_EQ(rows.size(), simulation.states.size());
  const io::NovatelLog log = io::read_novatel_enu(folder / "ins/novatel_enu.csv");
  EXPECT_EQ(log.records.size(), simulation.ins.size());
}

TEST(Simulation, DrawnMountingsArePlausible) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Simulation simulation = simulate(short_urban_drive(seed));
    const io::SensorMounting& ins = simulation.truth.vehicle_from_sensor.at("ins");
    EXPECT_LE(std::abs(deg_from_rad(ins.rotation.yaw)), 5.0);
    EXPECT_LE(std::abs(deg_from_rad(ins.rotation.pitch)), 3.0);
    EXPECT_LE(std::abs(deg_from_rad(ins.rotation.roll)), 3.0);
    EXPECT_GE(ins.translation.z(), 0.8);
  }
}

TEST(Simulation, InsYawMinusTrackDirectionIsTheMountingYawOnStraights) {
  // With the mounting's roll and pitch 0 the offset is the yaw alone: RTK heading noise 0.05 deg
  // white (negligible over >500 samples) plus a 0.02 deg Gauss-Markov bias: within 0.07 deg (3.5
  // sigma of the bias).
  SimulationOptions options = short_urban_drive(11);
  io::SensorMounting mounting;
  mounting.translation = {1.0, 0.2, 1.1};
  mounting.rotation = {0.0, 0.0, rad_from_deg(2.0)};
  options.mountings["ins"] = mounting;
  const Simulation level = simulate(options);
  EXPECT_NEAR(deg_from_rad(mean_yaw_offset_on_straights(level)), 2.0, 0.07);

  // With roll and pitch too, the reported yaw also carries their coupling with the road's
  // crossfall and grade (second order: up to 3 deg x 3 % ~ 0.1 deg); the sign and size of the
  // yaw still dominate.
  mounting.rotation = {rad_from_deg(-2.5), rad_from_deg(2.8), rad_from_deg(-3.0)};
  options.mountings["ins"] = mounting;
  const Simulation tilted = simulate(options);
  EXPECT_NEAR(deg_from_rad(mean_yaw_offset_on_straights(tilted)), -3.0, 0.2);
}

SimulationOptions short_radar_drive(std::uint64_t seed) {
  SimulationOptions options = short_urban_drive(seed);
  options.duration_s = 30.0;
  options.sensors = {"ins", "radar"};
  return options;
}

// Every file under `folder`, by its path relative to it, with its bytes.
std::map<std::string, std::string> folder_bytes(const std::filesystem::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    files[std::filesystem::relative(entry.path(), folder).string()] =
        io::read_text_file(entry.path());
  }
  return files;
}

TEST(Simulation, RadarIsDeterministicAndLeavesTheOtherSensorsAsTheyWere) {
  const auto first = temp_folder("simulation_radar_a");
  const auto second = temp_folder("simulation_radar_b");
  const Simulation with_radar = simulate(short_radar_drive(5));
  write_simulation(with_radar, first);
  write_simulation(simulate(short_radar_drive(5)), second);
  const auto bytes = folder_bytes(first);
  EXPECT_EQ(bytes, folder_bytes(second));
  EXPECT_GT(bytes.size(), 100u);  // a file per scan (13.9 Hz)
  EXPECT_TRUE(bytes.contains("radar_truth.csv"));

  // Without the radar, the GNSS/INS writes the same bytes; with the LiDAR too, the LiDAR's
  // mounting and world are the same.
  SimulationOptions ins_only = short_radar_drive(5);
  ins_only.sensors = {"ins"};
  const auto without = temp_folder("simulation_radar_c");
  write_simulation(simulate(ins_only), without);
  EXPECT_EQ(io::read_text_file(without / "ins/novatel_enu.csv"), bytes.at("ins/novatel_enu.csv"));
  SimulationOptions lidar = short_radar_drive(5);
  lidar.sensors = {"ins", "lidar"};
  const Simulation lidar_only = simulate(lidar);
  lidar.sensors = {"ins", "lidar", "radar"};
  const Simulation all = simulate(lidar);
  EXPECT_EQ(lidar_only.truth.vehicle_from_sensor.at("lidar").translation,
            all.truth.vehicle_from_sensor.at("lidar").translation);
  EXPECT_EQ(lidar_only.world.objects.size(), all.world.objects.size());
  EXPECT_EQ(lidar_only.world.movers.size(), all.world.movers.size());
  EXPECT_EQ(all.truth.vehicle_from_sensor.at("radar").translation,
            with_radar.truth.vehicle_from_sensor.at("radar").translation);

  // A rerun into the same folder leaves no stale scan behind.
  io::write_text_file(first / "radar/2000-01-01-00-00-00-000.csv", "stale");
  write_simulation(with_radar, first);
  EXPECT_EQ(bytes, folder_bytes(first));
}

TEST(Simulation, DrawnRadarMountingSitsOnTheFrontBumper) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SimulationOptions options = short_urban_drive(seed);
    options.duration_s = 5.0;
    options.sensors = {"radar"};
    const io::SensorMounting radar = simulate(options).truth.vehicle_from_sensor.at("radar");
    EXPECT_GE(radar.translation.x(), 3.5);
    EXPECT_LE(radar.translation.x(), 3.9);
    EXPECT_GE(radar.translation.z(), 0.4);
    EXPECT_LE(radar.translation.z(), 0.6);
    EXPECT_LE(std::abs(deg_from_rad(radar.rotation.yaw)), 5.0);
    EXPECT_LE(std::abs(deg_from_rad(radar.rotation.pitch)), 1.0);
    EXPECT_LE(std::abs(deg_from_rad(radar.rotation.roll)), 1.0);
  }
}

TEST(Simulation, CameraWritesItsIntrinsicsAndMountingAndChangesNoOtherBytes) {
  SimulationOptions options = short_radar_drive(6);
  options.duration_s = 8.0;
  const auto without = temp_folder("simulation_camera_a");
  write_simulation(simulate(options), without);
  options.sensors = {"ins", "radar", "camera"};
  options.camera.intrinsics = core::camera_preset("automotive_1080p");
  options.camera.intrinsics.fx = 1100.0;
  options.camera_render.rate_hz = 0.25;  // 2 frames of 1920x1080: the images' own tests are
                                         // camera_writer_test.cpp's
  const auto with = temp_folder("simulation_camera_b");
  const Simulation simulation = simulate(options);
  write_simulation(simulation, with);

  const io::GroundTruth truth = io::read_ground_truth(with / "ground_truth.yaml");
  ASSERT_TRUE(truth.vehicle_from_sensor.contains("camera"));
  EXPECT_EQ(truth.vehicle_from_sensor.at("camera").rotation.yaw,
            simulation.truth.vehicle_from_sensor.at("camera").rotation.yaw);
  EXPECT_EQ(io::read_camera_info_yaml(with / "camera" / kCameraIntrinsicsFile),
            options.camera.intrinsics);
  EXPECT_EQ(io::read_kitti_calib_cam(with / "camera" / kCameraKittiCalibFile, 2,
                                     io::KittiImages::kUnrectified),
            options.camera.intrinsics);
  // calib_time is the log's time 0 (UTC), in KITTI's form.
  ASSERT_EQ(options.start_unix_time, 1780308000.0);
  EXPECT_EQ(io::read_text_file(with / "camera" / kCameraKittiCalibFile).substr(0, 33),
            "calib_time: 01-Jun-2026 10:00:00\n");

  // Every other file is the same, byte for byte; the ground truth only gains the camera.
  auto others = folder_bytes(with);
  EXPECT_TRUE(others.contains("camera/images/0000000001.png"));
  EXPECT_TRUE(others.contains("camera/labels.csv"));
  std::erase_if(others, [](const auto& file) { return file.first.starts_with("camera/"); });
  const auto before = folder_bytes(without);
  const std::string truth_before = before.at("ground_truth.yaml");
  const std::string truth_after = others.at("ground_truth.yaml");
  others.erase("ground_truth.yaml");
  auto before_others = before;
  before_others.erase("ground_truth.yaml");
  EXPECT_EQ(others, before_others);
  io::GroundTruth truth_without = io::parse_ground_truth(truth_before, "before");
  truth_without.vehicle_from_sensor["camera"] = truth.vehicle_from_sensor.at("camera");
  EXPECT_EQ(io::format_ground_truth(truth_without), truth_after);
}

TEST(Simulation, DrawnCameraMountingSitsBehindTheWindscreen) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SimulationOptions options = short_urban_drive(seed);
    options.duration_s = 5.0;
    options.sensors = {"camera"};
    const Simulation simulation = simulate(options);
    const io::SensorMounting camera = simulation.truth.vehicle_from_sensor.at("camera");
    EXPECT_GE(camera.translation.x(), 1.5);
    EXPECT_LE(camera.translation.x(), 2.0);
    EXPECT_GE(camera.translation.z(), 1.3);
    EXPECT_LE(camera.translation.z(), 1.5);
    EXPECT_LE(std::abs(deg_from_rad(camera.rotation.yaw)), 5.0);
    EXPECT_LE(std::abs(deg_from_rad(camera.rotation.pitch)), 3.0);
    EXPECT_LE(std::abs(deg_from_rad(camera.rotation.roll)), 3.0);
    ASSERT_TRUE(simulation.camera.has_value());
    EXPECT_EQ(*simulation.camera, core::camera_preset("kitti"));
  }
}

TEST(Simulation, CameraMountingIsItsBodyFrameAndTheOpticalAxisLooksAlongIt) {
  // vehicle_from_camera is the body frame (x forward); the optical axis (z of O) is its x axis.
  // Pitched down 2 deg, the optical axis points 2 deg below the horizon, forward.
  const io::SensorMounting pitched{{1.8, 0.0, 1.4}, {0.0, rad_from_deg(2.0), 0.0}};
  const Eigen::Vector3d optical_axis_in_vehicle = pitched.vehicle_from_sensor().linear() *
                                                  camera_body_from_optical() *
                                                  Eigen::Vector3d::UnitZ();
  EXPECT_GT(optical_axis_in_vehicle.x(), 0.99);
  EXPECT_NEAR(std::asin(-optical_axis_in_vehicle.z()), rad_from_deg(2.0), 1e-12);
  // Image x (right) is the vehicle's -y, image y (down) its -z, for a level camera.
  const Eigen::Matrix3d level = camera_body_from_optical();
  EXPECT_TRUE(level.col(0).isApprox(-Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(level.col(1).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(level.determinant(), 1.0, 1e-15);
}

// One row of radar_truth.csv.
struct RadarTruthRow {
  int track_id = 0;
  std::string source;
  bool moving = false;
};

std::vector<RadarTruthRow> read_radar_truth(const std::filesystem::path& path) {
  std::vector<RadarTruthRow> rows;
  const std::string text = io::read_text_file(path);
  for (const io::TextLine& line : io::split_lines(text)) {
    if (line.number == 1) continue;  // header
    const std::vector<std::string_view> fields = io::split_fields(line.text);
    EXPECT_EQ(fields.size(), 8u);
    rows.push_back({std::stoi(std::string(fields[1])), std::string(fields[2]), fields[4] == "1"});
  }
  return rows;
}

// Everything from the files x2car simulate wrote to `folder`: the Conti scans of radar `sensor`,
// their truth (which detections are static scene objects), the trajectory and the true mounting;
// the Doppler fit starts from `start_yaw` [rad].
void expect_static_targets_follow_the_true_yaw(const std::filesystem::path& folder,
                                               const std::string& sensor, double start_yaw) {
  SCOPED_TRACE(sensor);
  const io::GroundTruth truth = io::read_ground_truth(folder / "ground_truth.yaml");
  ASSERT_TRUE(truth.vehicle_from_sensor.contains(sensor));
  const double true_yaw = truth.vehicle_from_sensor.at(sensor).rotation.yaw;
  const auto trajectory = io::read_trajectory_csv(folder / truth.trajectory_file);
  const io::RadarLog log = io::read_radar(folder / sensor, io::RadarLayout::kConti);
  const std::vector<RadarTruthRow> sources = read_radar_truth(folder / radar_truth_file(sensor));
  ASSERT_EQ(log.detections.size(), sources.size());
  const double clock_offset = log.start_unix_time - io::kDefaultStartUnixTime;

  // Static targets seen on straights at speed, with the car's speed at their time. There the
  // radar moves with the car, so range_rate = -v cos(azimuth + yaw) (io/radar_csv.hpp).
  struct Static {
    double v, azimuth, range_rate;
  };
  std::vector<Static> statics;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const io::RadarDetection& d = log.detections[i];
    ASSERT_EQ(d.track_id, sources[i].track_id) << i;
    if (sources[i].source != "target" || sources[i].moving) continue;
    const double time = d.time + clock_offset;
    const auto row = static_cast<std::size_t>(std::lround(time * 100.0));
    ASSERT_LT(row, trajectory.size());
    ASSERT_NEAR(trajectory[row].time, time, 0.006);
    const io::TrajectoryRow& state = trajectory[row];
    if (!state.straight || state.speed < 3.0 || std::abs(state.yaw_rate) > 0.005) continue;
    statics.push_back({state.speed, d.azimuth, d.range_rate});
  }
  ASSERT_GT(statics.size(), 200u);
  const auto residuals = [&](double yaw) {
    std::vector<double> r;
    for (const Static& s : statics) r.push_back(s.range_rate + s.v * std::cos(s.azimuth + yaw));
    return r;
  };
  // At the true yaw the residuals are the noise: range rate 0.1 m/s plus azimuth 0.3 deg times
  // v sin(azimuth + yaw) (up to ~0.07 m/s at 50 km/h).
  const std::vector<double> at_truth = residuals(true_yaw);
  EXPECT_NEAR(weighted_mean(at_truth), 0.0, 0.02);
  double square_sum = 0.0;
  for (const double r : at_truth) square_sum += r * r;
  EXPECT_LT(std::sqrt(square_sum / static_cast<double>(at_truth.size())), 0.15);
  // The least-squares yaw (Gauss-Newton on the relation) is the true one.
  double yaw = start_yaw;
  for (int iteration = 0; iteration < 10; ++iteration) {
    double jtj = 0.0;
    double jtr = 0.0;
    for (const Static& s : statics) {
      const double jacobian = -s.v * std::sin(s.azimuth + yaw);
      jtj += jacobian * jacobian;
      jtr += jacobian * (s.range_rate + s.v * std::cos(s.azimuth + yaw));
    }
    yaw -= jtr / jtj;
  }
  EXPECT_NEAR(deg_from_rad(angle_difference(yaw, true_yaw)), 0.0, 0.1);
}

TEST(Simulation, StaticRadarTargetsSatisfyTheDopplerRelationWithTheTrueYaw) {
  const auto folder = temp_folder("simulation_radar_doppler");
  SimulationOptions options = short_radar_drive(9);
  options.duration_s = 40.0;
  write_simulation(simulate(options), folder);
  expect_static_targets_follow_the_true_yaw(folder, "radar", 0.0);
}

// Issue 12: several radars on one car, each at its place and facing its way, in its own folder
// with its own truth; the front radar "radar" is the same as without the others.
TEST(Simulation, SeveralRadarsOnOneCar) {
  const auto folder = temp_folder("simulation_radars");
  SimulationOptions options = short_radar_drive(9);
  options.duration_s = 25.0;
  options.sensors = {"ins", "radar", "radar_left", "radar_rear", "radar_front_right"};
  const Simulation simulation = simulate(options);
  write_simulation(simulation, folder);
  EXPECT_EQ(simulation.radars.size(), 4u);
  const io::GroundTruth truth = io::read_ground_truth(folder / "ground_truth.yaml");
  for (const RadarPosition& position : radar_positions()) {
    const std::string sensor = "radar_" + position.name;
    if (!truth.vehicle_from_sensor.contains(sensor)) continue;
    const io::SensorMounting& mounting = truth.vehicle_from_sensor.at(sensor);
    EXPECT_LE(std::abs(deg_from_rad(
                  angle_difference(mounting.rotation.yaw, rad_from_deg(position.nominal_yaw_deg)))),
              5.0)
        << sensor;
    EXPECT_LE(std::abs(deg_from_rad(mounting.rotation.pitch)), 1.0);
    EXPECT_TRUE(std::filesystem::exists(folder / radar_truth_file(sensor)));
    expect_static_targets_follow_the_true_yaw(folder, sensor,
                                              rad_from_deg(position.nominal_yaw_deg));
  }
  const io::SensorMounting& left = truth.vehicle_from_sensor.at("radar_left");
  EXPECT_GT(left.translation.y(), 0.7);  // on the left side, ahead of the front axle
  EXPECT_GT(left.translation.x(), 2.8);
  EXPECT_LT(truth.vehicle_from_sensor.at("radar_rear").translation.x(), -0.7);  // rear bumper
  EXPECT_LT(truth.vehicle_from_sensor.at("radar_front_right").translation.y(), -0.5);
  // The front radar's files are those of a car with it alone.
  const auto alone = temp_folder("simulation_radars_alone");
  options.sensors = {"ins", "radar"};
  write_simulation(simulate(options), alone);
  EXPECT_TRUE(folder_bytes(alone / "radar") == folder_bytes(folder / "radar"));
  EXPECT_TRUE(is_radar_sensor("radar_rear_left"));
  EXPECT_FALSE(is_radar_sensor("radar_roof"));
}

// A cluster radar (RadarOptions::track_ids false) writes no ids: the Conti files' id fields are
// empty and read back as io::kNoTrackId; the detections are otherwise those of the tracking radar.
TEST(Simulation, ClusterRadarWritesNoTrackIds) {
  SimulationOptions options = short_radar_drive(4);
  options.duration_s = 10.0;
  const Simulation tracked = simulate(options);
  options.radar.track_ids = false;
  for (const io::RadarLayout layout :
       {io::RadarLayout::kConti, io::RadarLayout::kDelphi, io::RadarLayout::kGeneric}) {
    options.radar_layout = layout;
    const auto folder = temp_folder("simulation_clusters_" + io::to_string(layout));
    write_simulation(simulate(options), folder);
    const io::RadarLog log = io::read_radar(folder / "radar", io::RadarReadOptions{});
    EXPECT_EQ(log.layout, layout);
    const std::vector<io::RadarDetection> expected = radar_measurements(tracked.radars.at("radar"));
    ASSERT_EQ(log.detections.size(), expected.size());
    for (const io::RadarDetection& detection : log.detections) {
      EXPECT_EQ(detection.track_id, io::kNoTrackId);
      EXPECT_FALSE(detection.new_track);
    }
  }
}

// InsOptions::velocity_scale scales the reported velocity (a CAN speed's error), not the position.
TEST(Simulation, InsVelocityScaleScalesTheSpeedOnly) {
  SimulationOptions options = short_urban_drive(2);
  options.duration_s = 20.0;
  options.ins.velocity_sigma_horizontal = 0.0;
  options.ins.velocity_sigma_vertical = 0.0;
  const Simulation plain = simulate(options);
  options.ins.velocity_scale = 1.02;
  const Simulation scaled = simulate(options);
  ASSERT_EQ(plain.ins.size(), scaled.ins.size());
  for (std::size_t i = 0; i < plain.ins.size(); i += 97) {
    EXPECT_TRUE(scaled.ins[i].velocity_enu.isApprox(1.02 * plain.ins[i].velocity_enu, 1e-12));
    EXPECT_EQ(scaled.ins[i].position_enu, plain.ins[i].position_enu);
  }
  options.ins.velocity_scale = 0.2;
  EXPECT_THROW(simulate(options), std::invalid_argument);
}

// A KITTI pose file (camera poses: x right, y down, z forward) of a drive that stands 2 s, goes
// 100 m east at 10 m/s, turns left on a 40 m arc and goes on north, at 10 Hz; returns the
// path's horizontal positions in ENU, one per pose.
std::vector<Eigen::Vector2d> write_kitti_drive(const std::filesystem::path& file) {
  constexpr double kRadius = 40.0, kSpeed = 10.0;
  const double arc = kPi / 2.0 * kRadius;
  std::vector<Eigen::Vector2d> path;
  std::string text;
  for (int i = 0; i <= 300; ++i) {
    const double d = std::max(0.0, kSpeed * (i * 0.1 - 2.0));  // distance driven [m]
    Eigen::Vector2d east_north;
    if (d <= 100.0) {
      east_north = {d, 0.0};
    } else if (d <= 100.0 + arc) {
      const double angle = (d - 100.0) / kRadius;
      east_north = {100.0 + kRadius * std::sin(angle), kRadius * (1.0 - std::cos(angle))};
    } else {
      east_north = {100.0 + kRadius, kRadius + d - 100.0 - arc};
    }
    path.push_back(east_north);
    // x = -north, y = -up, z = east; identity rotation.
    text += io::format_numbers({1, 0, 0, -east_north.y(), 0, 1, 0, 0.0, 0, 0, 1, east_north.x()}) +
            "\n";
  }
  io::write_text_file(file, text);
  return path;
}

TEST(Simulation, RecordedKittiPathIsDrivenAlongItsTrack) {
  const auto folder = temp_folder("simulation_recorded");
  std::filesystem::create_directories(folder);
  const std::vector<Eigen::Vector2d> path = write_kitti_drive(folder / "poses.txt");
  SimulationOptions options = short_urban_drive(4);
  options.duration_s = 1000.0;  // the recording's 30 s
  options.sensors = {"ins", "radar"};
  options.recorded_path = kitti_poses_to_z_up(io::read_kitti_poses(folder / "poses.txt"));
  const auto out = folder / "drive";
  write_simulation(simulate(options), out);
  const auto rows = io::read_trajectory_csv(out / "trajectory.csv");
  ASSERT_EQ(rows.size(), 3001u);  // 30 s at 100 Hz
  // At every pose time the car is where the file says (within the fit's centimetres), and it
  // stands while the recording stands.
  double worst = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const io::TrajectoryRow& row = rows[10 * i];
    worst = std::max(worst, (row.world_from_vehicle.translation().head<2>() - path[i]).norm());
  }
  // The track jumps from straight to the arc's curvature, which no car can; the fit rounds the
  // corner over its preview (0.19 m at worst here); elsewhere it stays within centimetres.
  EXPECT_LT(worst, 0.25);
  EXPECT_EQ(rows[150].speed, 0.0);
  EXPECT_NEAR(rows[500].speed, 10.0, 1e-6);
  const Eigen::Matrix3d& rotation = rows.back().world_from_vehicle.linear();
  EXPECT_NEAR(std::atan2(rotation(1, 0), rotation(0, 0)), kPi / 2.0, rad_from_deg(1.0));  // north
  // The radar sees a world built around it.
  EXPECT_TRUE(std::filesystem::exists(out / kRadarTruthFile));
}

// A recording that cannot be driven is the user's file's fault: with recorded_path_file set (as
// `x2car simulate --trajectory` sets it) the error is an InputError naming that file.
TEST(Simulation, UndrivableRecordingNamesItsFile) {
  SimulationOptions options = short_urban_drive(1);
  options.duration_s = 1000.0;
  const auto pose_at = [](double time, double east) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(east, 0.0, 0.0);
    return StampedPose{time, pose};
  };
  options.recorded_path = {pose_at(0.0, 0.0), pose_at(0.5, 5.0)};  // shorter than 1 s
  EXPECT_THROW(simulate(options), std::invalid_argument);          // no file to name
  options.recorded_path_file = "drive_tum.txt";
  x2car::testing::expect_input_error([&] { simulate(options); }, "drive_tum.txt", 0);
  options.recorded_path = {pose_at(0.0, 0.0), pose_at(2.0, 0.5)};  // 0.5 m long
  const InputError error =
      x2car::testing::expect_input_error([&] { simulate(options); }, "drive_tum.txt", 0);
  EXPECT_THAT(error.what(), ::testing::HasSubstr("at least 1 m long"));
  // A jump of 1e7 m fails at once instead of fitting ten million knots first.
  options.recorded_path = {pose_at(0.0, 0.0), pose_at(2.0, 1e7)};
  x2car::testing::expect_input_error([&] { simulate(options); }, "drive_tum.txt", 0);
}

TEST(Simulation, RejectsSensorsItDoesNotModelYet) {
  SimulationOptions options = short_urban_drive(1);
  options.sensors = {"ins", "sonar"};
  EXPECT_THROW(simulate(options), std::invalid_argument);
  options.sensors = {"ins"};
  options.duration_s = 0.0;
  EXPECT_THROW(simulate(options), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::sim
