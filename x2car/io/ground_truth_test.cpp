#include "x2car/io/ground_truth.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;

GroundTruth sample_truth() {
  GroundTruth truth;
  truth.scenario = "urban";
  truth.seed = std::numeric_limits<std::uint64_t>::max();
  truth.duration_s = 60.0 / 7.0;
  truth.trajectory_file = "trajectory.csv";
  truth.vehicle_from_sensor["ins"] = {{0.1, -1.0 / 3.0, 1.2}, {0.0, 1e-20, rad_from_deg(-1.7)}};
  truth.vehicle_from_sensor["lidar"] = {{1.1, 0.0, 1.93}, {rad_from_deg(0.4), 0.02, 0.07}};
  truth.vehicle_from_sensor["radar"] = {{3.6, 0.05, 0.5}, {0.0, 0.0, -0.0873}};
  truth.vehicle_from_sensor["camera"] = {{1.5, 0.0, 1.4}, {-0.01, rad_from_deg(2.9), 3.1}};
  truth.vehicle_from_sensor["thermal_2"] = {{-0.5, 0.5, 2.0}, {0.1, -0.2, -3.1}};
  return truth;
}

void expect_same_mountings(const SensorMountings& actual, const SensorMountings& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (const auto& [sensor, e] : expected) {
    ASSERT_TRUE(actual.contains(sensor)) << sensor;
    const SensorMounting& a = actual.at(sensor);
    EXPECT_EQ(a.translation, e.translation) << sensor;
    EXPECT_EQ(a.rotation.roll, e.rotation.roll) << sensor;
    EXPECT_EQ(a.rotation.pitch, e.rotation.pitch) << sensor;
    EXPECT_EQ(a.rotation.yaw, e.rotation.yaw) << sensor;
  }
}

InputError expect_yaml_error(const std::string& text, std::size_t line, const std::string& field,
                             bool mountings_only = false) {
  return x2car::testing::expect_input_error(
      [&] {
        if (mountings_only) {
          parse_mountings(text, "truth.yaml");
        } else {
          parse_ground_truth(text, "truth.yaml");
        }
      },
      "truth.yaml", line, field);
}

constexpr char kHead[] = "scenario: urban\nseed: 3\nduration_s: 60\ntrajectory: trajectory.csv\n";

TEST(GroundTruth, RoundTripsExactly) {
  const GroundTruth truth = sample_truth();
  const std::string text = format_ground_truth(truth);
  const GroundTruth back = parse_ground_truth(text, "truth.yaml");
  EXPECT_EQ(back.scenario, truth.scenario);
  EXPECT_EQ(back.seed, truth.seed);
  EXPECT_EQ(back.duration_s, truth.duration_s);
  EXPECT_EQ(back.trajectory_file, truth.trajectory_file);
  expect_same_mountings(back.vehicle_from_sensor, truth.vehicle_from_sensor);
  EXPECT_EQ(format_ground_truth(back), text);  // and the text is stable
}

TEST(GroundTruth, WritesTheDocumentedKeys) {
  const std::string text = format_ground_truth(sample_truth());
  for (const char* key :
       {"\nscenario: urban\n", "\nseed: 18446744073709551615\n", "\ntrajectory: trajectory.csv\n",
        "\nvehicle_from_ins:\n  x: 0.1\n", "\nvehicle_from_lidar:\n", "\nvehicle_from_radar:\n",
        "\nvehicle_from_camera:\n", "\n  yaw: -0.0873\n"}) {
    EXPECT_THAT(text, HasSubstr(key));
  }
}

TEST(GroundTruth, StringsThatNeedQuotingRoundTrip) {
  GroundTruth truth = sample_truth();
  truth.scenario = "urban: #2 'rainy'";
  truth.trajectory_file = "null";
  const GroundTruth back = parse_ground_truth(format_ground_truth(truth), "truth.yaml");
  EXPECT_EQ(back.scenario, truth.scenario);
  EXPECT_EQ(back.trajectory_file, truth.trajectory_file);
}

TEST(GroundTruth, WriterRejectsSensorNamesTheReaderCouldNotKeep) {
  GroundTruth truth = sample_truth();
  truth.vehicle_from_sensor["front lidar"] = {};
  EXPECT_THROW(format_ground_truth(truth), std::invalid_argument);
}

TEST(GroundTruth, MountingGivesTheExtrinsicOfDesign1) {
  const SensorMounting mounting{{1.0, 2.0, 3.0}, {0.0, 0.0, kPi / 2}};  // yawed left 90 deg
  const Eigen::Isometry3d vehicle_from_sensor = mounting.vehicle_from_sensor();
  // The sensor's x axis points along the vehicle's y axis (left); its origin sits at t.
  EXPECT_TRUE((vehicle_from_sensor * Eigen::Vector3d(1, 0, 0))
                  .isApprox(Eigen::Vector3d(1.0, 3.0, 3.0), 1e-15));
  const SensorMounting back = mounting_from_transform(vehicle_from_sensor);
  EXPECT_EQ(back.translation, mounting.translation);
  EXPECT_NEAR(back.rotation.yaw, kPi / 2, 1e-15);
}

TEST(GroundTruth, MissingKeyIsNamed) {
  expect_yaml_error("scenario: urban\nduration_s: 60\ntrajectory: t.csv\n", 1, "seed");
  const std::string text =
      std::string(kHead) + "vehicle_from_lidar:\n  x: 1\n  y: 0\n  z: 2\n  roll: 0\n  yaw: 0\n";
  expect_yaml_error(text, 6, "vehicle_from_lidar.pitch");
}

TEST(GroundTruth, NonNumericValueIsNamedWithItsLine) {
  const std::string text =
      std::string(kHead) +
      "vehicle_from_ins:\n  x: 1\n  y: 0\n  z: abc\n  roll: 0\n  pitch: 0\n  yaw: 0\n";
  expect_yaml_error(text, 8, "vehicle_from_ins.z");
  expect_yaml_error("scenario: a\nseed: -1\nduration_s: 60\ntrajectory: t.csv\n", 2, "seed");
  expect_yaml_error("scenario: a\nseed: 1\nduration_s: .nan\ntrajectory: t.csv\n", 3, "duration_s");
  expect_yaml_error(std::string(kHead) + "vehicle_from_ins: [1, 2, 3]\n", 5, "vehicle_from_ins");
}

TEST(GroundTruth, UnknownSensorIsKeptAndUnknownKeysAreIgnored) {
  const std::string text = std::string(kHead) + "weather: rain\nvehicle_from_thermal:\n" +
                           "  x: 1\n  y: 2\n  z: 3\n  roll: 0.1\n  pitch: 0.2\n  yaw: 0.3\n";
  const GroundTruth truth = parse_ground_truth(text, "truth.yaml");
  ASSERT_EQ(truth.vehicle_from_sensor.size(), 1u);
  EXPECT_EQ(truth.vehicle_from_sensor.at("thermal").rotation.yaw, 0.3);
  EXPECT_EQ(truth.seed, 3u);
}

TEST(GroundTruth, InvalidYamlNamesTheLine) {
  expect_yaml_error("scenario: urban\nseed: [1, 2\n", 3, "");
  expect_yaml_error("- just\n- a list\n", 0, "");
}

TEST(Mountings, PartialFileWithOnlySomeSensorsIsAccepted) {
  const std::string text =
      "# --mounting file\nvehicle_from_lidar:\n  x: 1.2\n  y: 0\n  z: 1.9\n"
      "  roll: 0.01\n  pitch: -0.02\n  yaw: 0.05\n";
  const SensorMountings mountings = parse_mountings(text, "truth.yaml");
  ASSERT_EQ(mountings.size(), 1u);
  EXPECT_EQ(mountings.at("lidar").translation, Eigen::Vector3d(1.2, 0, 1.9));
  EXPECT_EQ(mountings.at("lidar").rotation.pitch, -0.02);
  expect_yaml_error(text, 2, "scenario");  // a full ground-truth file needs the rest
}

TEST(Mountings, GroundTruthFileIsAMountingFile) {
  const GroundTruth truth = sample_truth();
  expect_same_mountings(parse_mountings(format_ground_truth(truth), "truth.yaml"),
                        truth.vehicle_from_sensor);
}

TEST(Mountings, FileWithoutMountingsIsRejected) {
  const InputError error = expect_yaml_error(kHead, 0, "", true);
  EXPECT_THAT(error.what(), HasSubstr("vehicle_from_"));
  expect_yaml_error("vehicle_from_: {x: 0}\n", 1, "vehicle_from_", true);
}

TEST(GroundTruth, WritesAndReadsAFile) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "x2car_ground_truth_test.yaml";
  write_ground_truth(path, sample_truth());
  EXPECT_EQ(read_ground_truth(path).seed, sample_truth().seed);
  EXPECT_EQ(read_mountings(path).size(), sample_truth().vehicle_from_sensor.size());
  std::filesystem::remove(path);
  EXPECT_THROW(read_ground_truth(path), InputError);
}

// ---- trajectory side file ----------------------------------------------------------------------

std::vector<TrajectoryRow> sample_rows() {
  std::vector<TrajectoryRow> rows;
  for (int i = 0; i < 50; ++i) {
    const double s = static_cast<double>(i);
    TrajectoryRow row;
    row.time = 0.01 * s;
    row.world_from_vehicle = make_transform(EulerAngles{0.01 * std::sin(s), -0.03, 3.0 + 0.01 * s},
                                            Eigen::Vector3d(100.0 + s / 3.0, -50.0, 2.0));
    row.velocity_enu = {-9.9, 0.1 * s, 0.3};
    row.speed = 9.95;
    row.yaw_rate = 0.1;
    row.curvature = 0.1 / 9.95;
    row.straight = i % 2 == 0;
    rows.push_back(row);
  }
  return rows;
}

TEST(TrajectoryCsv, RoundTrips) {
  const std::vector<TrajectoryRow> rows = sample_rows();
  const std::string text = format_trajectory_csv(rows);
  EXPECT_TRUE(
      text.starts_with("time,x,y,z,roll,pitch,yaw,vx,vy,vz,speed,yaw_rate,curvature,straight\n"));
  const std::vector<TrajectoryRow> back = parse_trajectory_csv(text, "trajectory.csv");
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(back[i].time, rows[i].time);
    EXPECT_EQ(back[i].world_from_vehicle.translation(), rows[i].world_from_vehicle.translation());
    EXPECT_TRUE(
        back[i].world_from_vehicle.linear().isApprox(rows[i].world_from_vehicle.linear(), 1e-15));
    EXPECT_EQ(back[i].velocity_enu, rows[i].velocity_enu);
    EXPECT_EQ(back[i].speed, rows[i].speed);
    EXPECT_EQ(back[i].yaw_rate, rows[i].yaw_rate);
    EXPECT_EQ(back[i].curvature, rows[i].curvature);
    EXPECT_EQ(back[i].straight, rows[i].straight);
  }
}

TEST(TrajectoryCsv, RejectsBadInput) {
  const std::string header = std::string(kTrajectoryCsvHeader) + "\n";
  const auto parse = [](const std::string& text) { parse_trajectory_csv(text, "traj.csv"); };
  EXPECT_THROW(parse("time,x,y\n"), InputError);
  try {
    parse(header + "0,0,0,0,0,0,0,0,0,0,0,0,0,2\n");
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 2u);
    EXPECT_EQ(error.field(), "straight");
  }
  try {
    parse(header + "0,0,0,0,0,0,0,0,0,0,0,0,0,1\n0,0,0,0,0,0,0,0,0,0,0,0,0,1\n");
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 3u);
    EXPECT_EQ(error.field(), "time");
  }
}

}  // namespace
}  // namespace x2car::io
