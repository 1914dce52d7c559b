// End-to-end tests of the x2car binary: what a user types, what they see, and the exit code.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/kitti_calib_cam.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

using ::testing::ContainsRegex;
using ::testing::HasSubstr;
using ::testing::Not;

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// With `timeout_s` > 0 the run is killed after that long (coreutils `timeout`, exit code 124), so
// that a test of a command that must not hang fails instead of hanging.
CliRun run_x2car(const std::string& arguments, int timeout_s = 0) {
  const std::string limit = timeout_s > 0 ? "timeout " + std::to_string(timeout_s) + " " : "";
  const std::string command = limit + std::string(X2CAR_BINARY) + " " + arguments + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (const std::size_t read = fread(buffer.data(), 1, buffer.size(), pipe)) {
    run.output.append(buffer.data(), read);
  }
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::filesystem::path write_temp_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path) << text;
  return path;
}

// The numbers a command printed, in order; an output that holds anything else gives fewer numbers
// than expected, since reading stops at the first token that is not a number.
std::vector<double> numbers_in(const std::string& output) {
  std::istringstream stream(output);
  std::vector<double> numbers;
  for (double number; stream >> number;) numbers.push_back(number);
  return numbers;
}

TEST(Cli, HelpListsTheWorkingSubcommands) {
  const CliRun run = run_x2car("--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("convert"));
  EXPECT_THAT(run.output, HasSubstr("Exit codes"));
}

TEST(Cli, VersionPrintsTheVersion) {
  const CliRun run = run_x2car("--version");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("x2car 0."));
}

TEST(Cli, UsageErrorsExitWithTwo) {
  EXPECT_EQ(run_x2car("").exit_code, 2);
  EXPECT_EQ(run_x2car("no-such-subcommand").exit_code, 2);
  EXPECT_EQ(run_x2car("convert --to no-such-form 1 2 3 4 5 6 7").exit_code, 2);
}

TEST(Convert, YawOfTwoDegreesGivesTheExpectedMatrix) {
  const CliRun run = run_x2car("convert --from xyzrpy-deg --to matrix 0 0 0 0 0 2");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> m = numbers_in(run.output);
  ASSERT_EQ(m.size(), 16u) << run.output;
  const double yaw = 2.0 * M_PI / 180.0;
  EXPECT_NEAR(m[0], std::cos(yaw), 1e-12);
  EXPECT_NEAR(m[4], std::sin(yaw), 1e-12);  // R(1,0) > 0: the sensor's x axis turned left
  EXPECT_NEAR(m[15], 1.0, 1e-15);
}

TEST(Convert, NegativeNumbersAndRoundTripThroughEveryForm) {
  const CliRun to_quaternion =
      run_x2car("convert --from xyzrpy-deg --to quaternion -- 1.5 -0.2 1.9 -0.5 1.25 -3");
  ASSERT_EQ(to_quaternion.exit_code, 0) << to_quaternion.output;
  const auto quaternion_file = write_temp_file("extrinsic_quaternion.txt", to_quaternion.output);
  const CliRun back = run_x2car("convert --input " + quaternion_file.string() + " --to xyzrpy-deg");
  ASSERT_EQ(back.exit_code, 0) << back.output;
  const std::vector<double> v = numbers_in(back.output);
  ASSERT_EQ(v.size(), 6u) << back.output;
  const double expected[6] = {1.5, -0.2, 1.9, -0.5, 1.25, -3};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(v[i], expected[i], 1e-9) << "value " << i;
}

TEST(Convert, AllPrintsEveryForm) {
  const CliRun run =
      run_x2car("convert --from xyzrpy-rad --child lidar -- 1 0 1.8 0.01 -0.02 0.03");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* form : {"xyzrpy-deg", "xyzrpy-rad", "matrix", "quaternion", "urdf", "autoware",
                           "reference", "base_link from lidar", "<joint", "Extrinsic:"}) {
    EXPECT_THAT(run.output, HasSubstr(form));
  }
}

TEST(Convert, ReadsTheReferenceToolsText) {
  const auto path = write_temp_file(
      "reference_extrinsic.txt",
      "Extrinsic:\n[0.999391,-0.0348995,0,0],[0.0348995,0.999391,0,0],[0,0,1,1.8],[0,0,0,1]\n");
  const CliRun run = run_x2car("convert --input " + path.string() + " --to xyzrpy-deg");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> v = numbers_in(run.output);
  ASSERT_EQ(v.size(), 6u) << run.output;
  EXPECT_NEAR(v[2], 1.8, 1e-12);
  EXPECT_NEAR(v[5], 2.0, 1e-4);  // 6-digit input
}

TEST(Convert, InvertSwapsTheFrames) {
  const CliRun run =
      run_x2car("convert --from xyzrpy-deg --child lidar --invert --to urdf 1 0 2 0 0 90");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("<parent link=\"lidar\""));
  EXPECT_THAT(run.output, HasSubstr("<child link=\"base_link\""));
}

TEST(Convert, SixNumbersWithoutAUnitAskForOne) {
  const CliRun run = run_x2car("convert 0 0 0 0 0 2");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_THAT(run.output, HasSubstr("xyzrpy-deg"));
}

TEST(Convert, BadInputNamesTheFileAndExitsWithTwo) {
  const CliRun missing = run_x2car("convert --input /no/such/extrinsic.txt");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.output, HasSubstr("/no/such/extrinsic.txt"));

  const auto path = write_temp_file("bad_matrix.txt", "1 0 0 0\n0 1 0 0\n0 0 x 0\n0 0 0 1\n");
  const CliRun bad = run_x2car("convert --from matrix --input " + path.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr(path.string() + ":3"));
  EXPECT_THAT(bad.output, Not(HasSubstr("unexpected failure")));
}

}  // namespace
}  // namespace x2car::cli

namespace x2car::cli {
namespace {

TEST(Simulate, WritesTheDriveAndItsGroundTruth) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate";
  std::filesystem::remove_all(folder);
  const CliRun run =
      run_x2car("simulate --scenario straight --duration 20 --seed 2 --out " + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("true mountings"));
  for (const char* file :
       {"ground_truth.yaml", "trajectory.csv", "ins/novatel_enu.csv", "ins/ins.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(folder / file)) << file;
  }
}

TEST(Simulate, MountingFileReplacesTheDrawnMounting) {
  const auto mounting = write_temp_file(
      "mounting.yaml",
      "vehicle_from_ins:\n  x: 1\n  y: 0\n  z: 1\n  roll: 0\n  pitch: 0\n  yaw: 0.0349\n");
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_mounting";
  const CliRun run = run_x2car("simulate --duration 10 --out " + folder.string() + " --mounting " +
                               mounting.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("1.9996"));  // 0.0349 rad in degrees
}

TEST(Simulate, BadArgumentsExitWithTwo) {
  const std::string out = " --out " + (std::filesystem::path(::testing::TempDir()) / "x").string();
  EXPECT_EQ(run_x2car("simulate --sensors sonar" + out).exit_code, 2);
  EXPECT_EQ(run_x2car("simulate --scenario moon" + out).exit_code, 2);
  EXPECT_EQ(run_x2car("simulate --duration -5" + out).exit_code, 2);
  EXPECT_EQ(run_x2car("simulate --duration 10").exit_code, 2);  // no --out
  const auto broken = write_temp_file("broken_mounting.yaml", "vehicle_from_ins:\n  x: one\n");
  const CliRun run = run_x2car("simulate --mounting " + broken.string() + out);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_THAT(run.output, HasSubstr(broken.string()));
  EXPECT_EQ(run_x2car("simulate --sensors lidar --lidar-beams 48" + out).exit_code, 2);
  EXPECT_EQ(run_x2car("simulate --sensors lidar --lidar-format las" + out).exit_code, 2);
  EXPECT_EQ(run_x2car("simulate --sensors radar --radar-format ars" + out).exit_code, 2);
}

TEST(Simulate, WritesLidarSweepsInTheChosenFormat) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_lidar";
  std::filesystem::remove_all(folder);
  const CliRun run = run_x2car("simulate --duration 1 --sensors ins,lidar --lidar-beams 32 " +
                               std::string("--lidar-format kitti --out ") + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("lidar: 32 beams at 10 Hz (kitti)"));
  EXPECT_THAT(run.output, HasSubstr("    lidar "));  // its true mounting
  EXPECT_TRUE(std::filesystem::exists(folder / "lidar/velodyne/000009.bin"));
  EXPECT_TRUE(std::filesystem::exists(folder / "lidar/times.txt"));
  EXPECT_FALSE(std::filesystem::exists(folder / "lidar/000000.000000.pcd"));
}

TEST(Simulate, CameraWritesIntrinsicsImagesAndLabelsBesideTheIns) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_camera";
  std::filesystem::remove_all(folder);
  const CliRun run = run_x2car(
      "simulate --duration 1 --sensors ins,camera --camera-format jpg --out " + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("camera: 1242x375, fx 721.538 fy 721.538"));
  EXPECT_THAT(run.output, HasSubstr("    camera "));  // its true mounting
  EXPECT_TRUE(std::filesystem::exists(folder / "ins/novatel_enu.csv"));
  const std::string text = io::read_text_file(folder / "camera/intrinsics.yaml");
  EXPECT_THAT(text, HasSubstr("image_width: 1242\n"));
  EXPECT_THAT(io::read_text_file(folder / "camera/calib_cam_to_cam.txt"),
              HasSubstr("\nP_rect_02: 721.5377 0 609.5593 0 0 721.5377 172.854 0 0 0 1 0\n"));
  const std::string truth_text = io::read_text_file(folder / "ground_truth.yaml");
  EXPECT_THAT(truth_text, HasSubstr("vehicle_from_camera:\n"));
  EXPECT_THAT(truth_text, HasSubstr("vehicle_from_ins:\n"));
  // Its images, one per frame at 10 Hz, their times and labels.
  EXPECT_THAT(run.output, HasSubstr("10 frames at 10 Hz (jpg)"));
  EXPECT_TRUE(std::filesystem::exists(folder / "camera/images/0000000009.jpg"));
  EXPECT_FALSE(std::filesystem::exists(folder / "camera/images/0000000010.jpg"));
  EXPECT_THAT(io::read_text_file(folder / "camera/timestamps.txt"),
              HasSubstr("\n2026-06-01 10:00:00.900000000\n"));
  EXPECT_TRUE(std::filesystem::exists(folder / "camera/labels.csv"));
}

TEST(Simulate, ConfigFileSetsParametersAndOptionsWinOverIt) {
  const auto config = write_temp_file(
      "cli_simulate_config.yaml",
      "ins:\n  heading_sigma_deg: 0.5\nlidar:\n  beams: 32\n  azimuth_step_deg: 2\n");
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_config";
  std::filesystem::remove_all(folder);
  const CliRun run = run_x2car("simulate --duration 1 --sensors ins,lidar --config " +
                               config.string() + " --out " + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("lidar: 32 beams at 10 Hz"));
  const CliRun printed = run_x2car("simulate --config " + config.string() + " --print-config");
  ASSERT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_THAT(printed.output, HasSubstr("  heading_sigma_deg: 0.5 "));
  EXPECT_THAT(printed.output, HasSubstr("  beams: 32 "));
  const CliRun explicit_beams =
      run_x2car("simulate --config " + config.string() + " --lidar-beams 128 --print-config");
  EXPECT_THAT(explicit_beams.output, HasSubstr("  beams: 128 "));
  EXPECT_THAT(explicit_beams.output, HasSubstr("  heading_sigma_deg: 0.5 "));
  // The INS noise took effect: with 0.5 deg of white heading noise, successive yaws (ins.csv's
  // 10th column) differ by 0.5 sqrt(2) = 0.71 deg rms; the default 0.05 deg gives 0.07 deg.
  std::ifstream ins(folder / "ins/ins.csv");
  std::string line;
  std::getline(ins, line);  // header
  std::vector<double> yaws;
  while (std::getline(ins, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    const std::vector<double> fields = numbers_in(line);
    ASSERT_EQ(fields.size(), 10u) << line;
    yaws.push_back(fields[9]);
  }
  ASSERT_GT(yaws.size(), 90u);
  double sum_squares = 0.0;
  for (std::size_t i = 1; i < yaws.size(); ++i) {
    sum_squares += std::pow(std::remainder(yaws[i] - yaws[i - 1], 2.0 * M_PI), 2);
  }
  const double rms_deg =
      std::sqrt(sum_squares / static_cast<double>(yaws.size() - 1)) * 180.0 / M_PI;
  EXPECT_GT(rms_deg, 0.5);
  EXPECT_LT(rms_deg, 0.95);
}

TEST(Simulate, ConfigErrorsExitWithTwoNamingTheKey) {
  const std::string out = " --out " + (std::filesystem::path(::testing::TempDir()) / "x").string();
  const auto unknown = write_temp_file("cli_simulate_config_unknown.yaml", "lidar:\n  beems: 32\n");
  const CliRun run = run_x2car("simulate --config " + unknown.string() + out);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_THAT(run.output, HasSubstr(unknown.string()));
  EXPECT_THAT(run.output, HasSubstr("lidar.beems"));
  const auto wrong = write_temp_file("cli_simulate_config_type.yaml", "ins:\n  rate_hz: fast\n");
  const CliRun type = run_x2car("simulate --config " + wrong.string() + out);
  EXPECT_EQ(type.exit_code, 2);
  EXPECT_THAT(type.output, HasSubstr("ins.rate_hz"));
  EXPECT_EQ(run_x2car("simulate --duration 1").exit_code, 2);  // no --out
}

// Values that ran past 60 s or into bad_alloc on a reviewer's 5 s drive are rejected at once,
// naming the file and the field.
TEST(Simulate, ConfigValuesThatCannotFinishExitWithTwoAtOnce) {
  const std::string out =
      " --duration 5 --sensors ins,lidar,radar --out " +
      (std::filesystem::path(::testing::TempDir()) / "cli_simulate_config_bounds").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"route:\n  vertical:\n    waves: 100000000\n", "waves"},
      {"world:\n  roadside:\n    pole_spacing_m: 1e-6\n", "pole_spacing_m"},
      {"world:\n  road:\n    max_station_step_m: 1e-7\n", "max_station_step_m"},
      {"world:\n  roadside:\n    guard_rail_post_spacing_m: 1e-5\n", "guard_rail_post_spacing_m"},
      {"world:\n  traffic:\n    oncoming_cars_per_km: 1e7\n", "oncoming_cars_per_km"},
      {"world_radar:\n  mover_sample_period_s: 1e-9\n", "mover_sample_period_s"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto config = write_temp_file("cli_simulate_config_bounds_" + std::to_string(i) + ".yaml",
                                        cases[i].first);
    const CliRun run = run_x2car("simulate --config " + config.string() + out, 30);
    EXPECT_EQ(run.exit_code, 2) << cases[i].first << run.output;
    EXPECT_THAT(run.output, HasSubstr(config.string()));
    EXPECT_THAT(run.output, HasSubstr(cases[i].second));
  }
}

// A TUM file of two short lines: the format detection read the file's text after it had been
// freed (a temporary in a range-for), so a short file's first line came back as garbage and
// `--trajectory-format auto` rejected a valid file.
TEST(Simulate, ShortTumTrajectoryIsDetectedAndDriven) {
  const auto trajectory =
      write_temp_file("cli_simulate_short_tum.txt", "0 0 0 0 0 0 0 1\n3 15 0 0 0 0 0 1\n");
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_short_tum";
  std::filesystem::remove_all(folder);
  const CliRun run = run_x2car("simulate --scenario straight --trajectory " + trajectory.string() +
                               " --out " + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(folder / "trajectory.csv"));
}

// A trajectory that cannot be driven is an input error naming the file, not a bare message.
TEST(Simulate, UndrivableTrajectoryExitsWithTwoNamingTheFile) {
  const std::string out =
      " --out " + (std::filesystem::path(::testing::TempDir()) / "cli_simulate_bad_tum").string();
  const auto brief = write_temp_file("cli_simulate_brief_tum.txt",
                                     "0 0 0 0 0 0 0 1\n0.5 5 0 0 0 0 0 1\n");  // 0.5 s
  const CliRun too_short = run_x2car("simulate --trajectory " + brief.string() + out, 60);
  EXPECT_EQ(too_short.exit_code, 2) << too_short.output;
  EXPECT_THAT(too_short.output, HasSubstr(brief.string()));
  EXPECT_THAT(too_short.output, HasSubstr("shorter than min_duration_s"));
  const auto tiny = write_temp_file("cli_simulate_tiny_tum.txt",
                                    "0 0 0 0 0 0 0 1\n2 0.5 0 0 0 0 0 1\n");  // 0.5 m
  const CliRun too_small = run_x2car("simulate --trajectory " + tiny.string() + out, 60);
  EXPECT_EQ(too_small.exit_code, 2) << too_small.output;
  EXPECT_THAT(too_small.output, HasSubstr(tiny.string()));
  EXPECT_THAT(too_small.output, HasSubstr("at least 1 m long"));
  const auto jump = write_temp_file("cli_simulate_jump_tum.txt",
                                    "0 0 0 0 0 0 0 1\n2 1e6 0 0 0 0 0 1\n4 2e6 0 0 0 0 0 1\n");
  const CliRun jumped = run_x2car("simulate --trajectory " + jump.string() + out, 60);
  EXPECT_EQ(jumped.exit_code, 2) << jumped.output;
  EXPECT_THAT(jumped.output, HasSubstr(jump.string()));
}

// The number after `key: ` in the text from `from` on; NAN when absent.
double number_after(const std::string& text, const std::string& from, const std::string& key) {
  const std::size_t start = text.find(from);
  const std::size_t at = start == std::string::npos ? start : text.find(key + ": ", start);
  return at == std::string::npos ? NAN : std::stod(text.substr(at + key.size() + 2));
}

TEST(Simulate, RadarDriveCalibratesToTheTrueYaw) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_simulate_radar";
  std::filesystem::remove_all(folder);
  const CliRun run = run_x2car("simulate --scenario urban --duration 60 --seed 3 " +
                               std::string("--sensors ins,radar --out ") + folder.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("radar: "));
  EXPECT_TRUE(std::filesystem::exists(folder / "radar_truth.csv"));
  const std::string truth = io::read_text_file(folder / "ground_truth.yaml");
  const double true_yaw_deg = number_after(truth, "vehicle_from_radar:", "yaw") * 180.0 / M_PI;
  const double x = number_after(truth, "vehicle_from_radar:", "x");
  const double y = number_after(truth, "vehicle_from_radar:", "y");
  ASSERT_TRUE(std::isfinite(true_yaw_deg)) << truth;

  const auto json = folder / "radar_result.json";
  const CliRun calibrate =
      run_x2car("calibrate radar --input " + (folder / "radar").string() + " --ins " +
                (folder / "ins/novatel_enu.csv").string() + " --lever-arm " + std::to_string(x) +
                " " + std::to_string(y) + " --out " + json.string());
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  const std::string result = io::read_text_file(json);
  // The Doppler of about a thousand static targets pins the yaw to a few hundredths of a degree;
  // 0.2 deg leaves room for the GNSS/INS's own heading and velocity errors.
  EXPECT_NEAR(number_after(result, "", "\"yaw_deg\""), true_yaw_deg, 0.2) << result;
}

}  // namespace
namespace {

// A drive simulated once for the calibrate tests, with the GNSS/INS yawed 2 deg left and pitched
// 1 deg down.
std::filesystem::path simulated_drive() {
  static const std::filesystem::path folder = [] {
    // One folder per test: ctest runs each test in its own process, several at once, and each
    // process simulates its drive afresh (a shared folder was wiped under a running test).
    const auto out = std::filesystem::path(::testing::TempDir()) /
                     (std::string("cli_calibrate_drive_") +
                      ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() +
                      "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(out);
    const auto mounting =
        write_temp_file("ins_mounting.yaml",
                        "vehicle_from_ins:\n  x: 1.2\n  y: 0.1\n  z: 1.0\n  roll: 0.01\n"
                        "  pitch: 0.017453292519943295\n  yaw: 0.03490658503988659\n");
    const CliRun run = run_x2car("simulate --scenario urban --duration 120 --seed 5 --out " +
                                 out.string() + " --mounting " + mounting.string());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return out;
  }();
  return folder;
}

TEST(CalibrateIns, RecoversTheSimulatedMountingAndWritesEveryForm) {
  const auto drive = simulated_drive();
  const auto json = drive / "ins_result.json";
  const auto yaml = drive / "ins_result.yaml";
  const auto urdf = drive / "ins_result.urdf";
  const CliRun run =
      run_x2car("calibrate ins --input " + (drive / "ins/novatel_enu.csv").string() + " --out " +
                json.string() + " --yaml " + yaml.string() + " --urdf " + urdf.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("roll   not observable"));
  const std::string text = io::read_text_file(json);
  EXPECT_THAT(text, HasSubstr("\"roll_deg\": null"));
  // "yaw_deg": 2.0xx and "pitch_deg": 1.0xx within 0.05 deg.
  const auto number_after = [&](const std::string& key) {
    const std::size_t at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? NAN : std::stod(text.substr(at + key.size() + 4));
  };
  EXPECT_NEAR(number_after("yaw_deg"), 2.0, 0.05);
  EXPECT_NEAR(number_after("pitch_deg"), 1.0, 0.05);
  EXPECT_TRUE(std::filesystem::exists(yaml));
  EXPECT_TRUE(std::filesystem::exists(urdf));
  // The generic CSV of the same drive gives the same answer.
  const CliRun generic = run_x2car("calibrate ins --input " + (drive / "ins/ins.csv").string());
  ASSERT_EQ(generic.exit_code, 0) << generic.output;
  EXPECT_THAT(generic.output, HasSubstr("yaw"));
}

// Issue 12: --turns exclude keeps the paper's straight-only gates; --lever-arm gives the sensor's
// position instead of fitting it.
TEST(CalibrateIns, TurnsAndLeverArmOptions) {
  const auto drive = simulated_drive();
  const std::string input = " --input " + (drive / "ins/novatel_enu.csv").string();
  const auto json = drive / "ins_turns.json";
  const auto number_after = [&](const std::string& key) {
    const std::string text = io::read_text_file(json);
    const std::size_t at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? NAN : std::stod(text.substr(at + key.size() + 4));
  };
  CliRun run =
      run_x2car("calibrate ins" + input + " --lever-arm 1.2 0.1 1.0 --out " + json.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(number_after("turns_used"), 1.0);
  EXPECT_EQ(number_after("lever_arm_x_m"), 1.2);
  EXPECT_NEAR(number_after("yaw_deg"), 2.0, 0.05);
  run = run_x2car("calibrate ins" + input + " --turns exclude --out " + json.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(number_after("turns_used"), 0.0);
  EXPECT_NEAR(number_after("yaw_deg"), 2.0, 0.05);
  EXPECT_EQ(run_x2car("calibrate ins" + input + " --turns sometimes").exit_code, 2);
  EXPECT_EQ(run_x2car("calibrate ins" + input + " --lever-arm 1 2").exit_code, 2);
}

TEST(CalibrateIns, TurningOnlyExitsWithOneAndSaysWhatIsMissing) {
  // 10 s on a 30 m circle at 8 m/s.
  std::string csv = "time,x,y,z,vx,vy,vz,roll,pitch,yaw\n";
  for (int i = 0; i <= 1000; ++i) {
    const double t = i * 0.01, angle = 8.0 * t / 30.0;
    csv += std::to_string(t) + "," + std::to_string(30 * std::sin(angle)) + "," +
           std::to_string(30 * (1 - std::cos(angle))) + ",0," +
           std::to_string(8 * std::cos(angle)) + "," + std::to_string(8 * std::sin(angle)) +
           ",0,0,0," + std::to_string(angle) + "\n";
  }
  const auto file = write_temp_file("circle_ins.csv", csv);
  const CliRun run = run_x2car("calibrate ins --input " + file.string());
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr("insufficient data"));
  EXPECT_THAT(run.output, HasSubstr("need 20 s"));
}

TEST(CalibrateIns, BadInputExitsWithTwoNamingTheFileAndLine) {
  const auto file = write_temp_file("nan_ins.csv",
                                    "time,x,y,z,vx,vy,vz,roll,pitch,yaw\n0,0,0,0,0,0,0,0,0,0\n"
                                    "0.01,nan,0,0,0,0,0,0,0,0\n");
  const CliRun run = run_x2car("calibrate ins --input " + file.string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_THAT(run.output, HasSubstr(file.string()));
  EXPECT_THAT(run.output, HasSubstr("3"));
  EXPECT_EQ(run_x2car("calibrate ins --input /no/such/file.csv").exit_code, 2);
  EXPECT_EQ(run_x2car("calibrate ins").exit_code, 2);
  EXPECT_EQ(run_x2car("calibrate").exit_code, 2);
}

}  // namespace
namespace {

// calibrate radar --method position and auto on a simulated drive (Conti layout, issue 6).
TEST(CalibrateRadar, PositionAndAutoMethods) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_radar_methods";
  std::filesystem::remove_all(folder);
  const CliRun simulate = run_x2car("simulate --scenario urban --duration 60 --seed 4 " +
                                    std::string("--sensors ins,radar --out ") + folder.string());
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  const std::string truth = io::read_text_file(folder / "ground_truth.yaml");
  const double true_yaw_deg = number_after(truth, "vehicle_from_radar:", "yaw") * 180.0 / M_PI;
  const std::string lever_arm = std::to_string(number_after(truth, "vehicle_from_radar:", "x")) +
                                " " +
                                std::to_string(number_after(truth, "vehicle_from_radar:", "y"));
  const std::string inputs = "calibrate radar --input " + (folder / "radar").string() + " --ins " +
                             (folder / "ins/novatel_enu.csv").string() + " --lever-arm " +
                             lever_arm;

  const auto json = folder / "position.json";
  const CliRun position = run_x2car(inputs + " --method position --out " + json.string());
  ASSERT_EQ(position.exit_code, 0) << position.output;
  EXPECT_THAT(position.output, HasSubstr("method position"));
  const std::string result = io::read_text_file(json);
  EXPECT_THAT(result, HasSubstr("\"static_objects\""));
  EXPECT_NEAR(number_after(result, "", "\"yaw_deg\""), true_yaw_deg, 0.2) << result;

  const CliRun automatic = run_x2car(inputs + " --method auto");
  ASSERT_EQ(automatic.exit_code, 0) << automatic.output;
  EXPECT_THAT(automatic.output, HasSubstr("note: auto: "));
  EXPECT_THAT(automatic.output, HasSubstr("reported the "));

  // Issue 12: a prior on the yaw, and the ego-speed scale in the summary.
  const auto velocity_json = folder / "velocity.json";
  const CliRun velocity =
      run_x2car(inputs + " --method velocity --nominal-yaw " + std::to_string(true_yaw_deg + 20.0) +
                " --out " + velocity_json.string());
  ASSERT_EQ(velocity.exit_code, 0) << velocity.output;
  EXPECT_THAT(velocity.output, HasSubstr("speed scale "));
  EXPECT_NEAR(number_after(io::read_text_file(velocity_json), "", "\"yaw_deg\""), true_yaw_deg,
              0.2);
  EXPECT_EQ(run_x2car(inputs + " --nominal-yaw 400").exit_code, 2);
}

// Issue 12: several radars on one car, cluster lists without track ids (--config radar.track_ids
// false); each radar's folder calibrates on its own by the position method (the detections
// associated into tracks). Measured on seed 4: |error| 0.05 deg (left, +91 deg), 0.04 deg (rear).
TEST(CalibrateRadar, SideAndRearClusterRadarsOfOneCar) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_radars";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const auto config = folder / "clusters.yaml";
  io::write_text_file(config, "radar:\n  track_ids: false\n");
  const auto drive = folder / "drive";
  const CliRun simulate = run_x2car(
      "simulate --scenario urban --duration 60 --seed 4 --sensors ins,radar_left,radar_rear "
      "--config " +
      config.string() + " --out " + drive.string());
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  EXPECT_THAT(simulate.output, HasSubstr("radar_left: "));
  const std::string truth = io::read_text_file(drive / "ground_truth.yaml");
  for (const std::string sensor : {"radar_left", "radar_rear"}) {
    SCOPED_TRACE(sensor);
    EXPECT_TRUE(std::filesystem::exists(drive / (sensor + "_truth.csv")));
    const std::string entry = "vehicle_from_" + sensor + ":";
    const double true_yaw_deg = number_after(truth, entry, "yaw") * 180.0 / M_PI;
    const auto json = folder / (sensor + ".json");
    const CliRun run =
        run_x2car("calibrate radar --method position --input " + (drive / sensor).string() +
                  " --ins " + (drive / "ins/novatel_enu.csv").string() + " --lever-arm " +
                  std::to_string(number_after(truth, entry, "x")) + " " +
                  std::to_string(number_after(truth, entry, "y")) + " --out " + json.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::string result = io::read_text_file(json);
    EXPECT_THAT(result, HasSubstr("\"associated_tracks\""));
    const double error_deg =
        std::remainder(number_after(result, "", "\"yaw_deg\"") - true_yaw_deg, 360.0);
    EXPECT_LE(std::abs(error_deg), 0.3) << result;
  }
}

}  // namespace
}  // namespace x2car::cli

namespace x2car::cli {
namespace {

// calibrate lidar (issue 5) through the files `simulate` writes.
TEST(CalibrateLidar, RecoversTheSimulatedMountingFromPcdFiles) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_lidar_drive";
  std::filesystem::remove_all(folder);
  const CliRun simulate = run_x2car(
      "simulate --scenario straight --duration 30 --seed 2 --sensors lidar --lidar-beams 32 "
      "--out " +
      folder.string());
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  const std::string truth = io::read_text_file(folder / "ground_truth.yaml");
  const auto json = folder / "lidar_result.json";
  const CliRun calibrate = run_x2car("calibrate lidar --input " + folder.string() + " --out " +
                                     json.string() + " --without-series");
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  EXPECT_THAT(calibrate.output, HasSubstr("found 300 sweeps"));
  const std::string result = io::read_text_file(json);
  constexpr double kDegPerRad = 180.0 / M_PI;
  for (const std::string angle : {"roll", "pitch", "yaw"}) {
    EXPECT_NEAR(number_after(result, "", "\"" + angle + "_deg\""),
                number_after(truth, "vehicle_from_lidar:", angle) * kDegPerRad, 0.1)
        << angle << "\n"
        << result;
  }
  EXPECT_NEAR(number_after(result, "", "\"z_m\""), number_after(truth, "vehicle_from_lidar:", "z"),
              0.02);
}

TEST(CalibrateLidar, BadFoldersExitWithTwoAndTooFewSweepsWithOne) {
  const auto root = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_lidar_bad";
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "empty");
  const CliRun empty = run_x2car("calibrate lidar --input " + (root / "empty").string());
  EXPECT_EQ(empty.exit_code, 2) << empty.output;
  EXPECT_THAT(empty.output, HasSubstr("holds no LiDAR sweeps"));

  const auto drive = root / "drive";
  const CliRun simulate = run_x2car(
      "simulate --scenario straight --duration 2.5 --seed 1 --sensors lidar --lidar-beams 32 "
      "--out " +
      drive.string());
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  std::filesystem::create_directories(root / "few");
  for (const std::string name :
       {"000000.000000", "000000.100000", "000000.200000", "000000.300000", "000000.400000"}) {
    std::filesystem::copy_file(drive / "lidar" / (name + ".pcd"), root / "few" / (name + ".pcd"));
  }
  const CliRun few = run_x2car("calibrate lidar --input " + (root / "few").string());
  EXPECT_EQ(few.exit_code, 1) << few.output;
  EXPECT_THAT(few.output, HasSubstr("only 5 sweeps"));

  const auto truncated = drive / "lidar" / "000000.200000.pcd";
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) / 2);
  const CliRun bad = run_x2car("calibrate lidar --input " + drive.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr(truncated.string()));
  EXPECT_THAT(bad.output, HasSubstr("truncated"));
}

// A drive folder as the simulator lays it out (camera/images/, timestamps.txt, intrinsics.yaml),
// with synthetic street images seen from a known mounting (camera/camera_test_support.hpp), the
// car driving at 10 m/s.
std::filesystem::path write_camera_drive(const std::string& name, int frames,
                                         double interval_s = 0.1) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder / "camera" / "images");
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  io::write_camera_info_yaml(folder / "camera" / "intrinsics.yaml", intrinsics);
  std::string timestamps;
  for (int i = 0; i < frames; ++i) {
    camera::testing::StreetScene scene;
    scene.vehicle_from_camera = {0.02, 0.05, -0.03};  // [rad]
    scene.travelled_m = 1.0 * i;
    scene.noise_seed = static_cast<std::uint64_t>(i + 1);
    char file[32];
    std::snprintf(file, sizeof file, "%010d.png", i);
    cv::imwrite((folder / "camera" / "images" / file).string(),
                camera::testing::draw_street(scene, intrinsics));
    timestamps += std::to_string(10.0 + interval_s * i) + "\n";
  }
  io::write_text_file(folder / "camera" / "timestamps.txt", timestamps);
  return folder;
}

// The default window is the paper's 100 frames at 10 Hz, as many seconds at the frames' rate (200
// frames at 20 Hz); --window-frames gives the count as is, at any rate. --max-frame-rate takes
// fewer frames of a fast camera, and the run says so when it is not given.
TEST(CalibrateCamera, TheWindowHoldsAsManySecondsUnlessItsFramesAreGiven) {
  const auto folder = write_camera_drive("cli_calibrate_camera_20_hz", 24, 0.05);
  const CliRun by_default = run_x2car("calibrate camera --input " + folder.string());
  EXPECT_EQ(by_default.exit_code, 1) << by_default.output;
  EXPECT_THAT(by_default.output, HasSubstr("need 200"));
  EXPECT_THAT(by_default.output, HasSubstr("the frames run at 20 Hz"));
  EXPECT_THAT(by_default.output, HasSubstr("--max-frame-rate 10 (the paper's camera's rate) keeps "
                                           "one frame in 2 and runs about 2 times as fast"));
  // At most 10 Hz: every other frame, 12 at 10 Hz, and the paper's window of 100 frames.
  const CliRun fewer =
      run_x2car("calibrate camera --input " + folder.string() + " --max-frame-rate 10");
  EXPECT_EQ(fewer.exit_code, 1) << fewer.output;
  EXPECT_THAT(fewer.output, HasSubstr("need 100"));
  EXPECT_THAT(fewer.output, Not(HasSubstr("the frames run at")));
  EXPECT_EQ(
      run_x2car("calibrate camera --input " + folder.string() + " --max-frame-rate 0").exit_code,
      2);
  // Frames kept 0.35 s apart are too far for the motion estimator's pairs (0.25 s).
  const CliRun too_few = run_x2car("calibrate camera --input " + folder.string() +
                                   " --estimator motion --max-frame-rate 3");
  EXPECT_EQ(too_few.exit_code, 2) << too_few.output;
  EXPECT_THAT(too_few.output, HasSubstr("max_pair_gap_s"));
  const auto json = folder / "camera_result.json";
  const CliRun given = run_x2car("calibrate camera --input " + folder.string() +
                                 " --window-frames 12 --out " + json.string());
  ASSERT_EQ(given.exit_code, 0) << given.output;
  EXPECT_THAT(given.output, HasSubstr("windows 2"));
  const CliRun help = run_x2car("calibrate camera --help");
  EXPECT_THAT(help.output, HasSubstr("100 at 10 Hz"));
  EXPECT_THAT(help.output, HasSubstr("--max-frame-rate HZ"));
}

TEST(CalibrateCamera, RecoversTheMountingFromAFolderOfImages) {
  const auto folder = write_camera_drive("cli_calibrate_camera_drive", 24);
  const auto json = folder / "camera_result.json";
  const CliRun calibrate =
      run_x2car("calibrate camera --input " + folder.string() +
                " --window-frames 12 --without-series --out " + json.string() + " --yaml " +
                (folder / "camera.yaml").string() + " --urdf " + (folder / "camera.urdf").string());
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  EXPECT_THAT(calibrate.output, HasSubstr("found 24 images"));
  EXPECT_THAT(calibrate.output, Not(HasSubstr("--max-frame-rate")));  // 10 Hz
  const std::string result = io::read_text_file(json);
  constexpr double kDegPerRad = 180.0 / M_PI;
  EXPECT_NEAR(number_after(result, "", "\"roll_deg\""), 0.02 * kDegPerRad, 0.1) << result;
  EXPECT_NEAR(number_after(result, "", "\"pitch_deg\""), 0.05 * kDegPerRad, 0.1) << result;
  EXPECT_NEAR(number_after(result, "", "\"yaw_deg\""), -0.03 * kDegPerRad, 0.1) << result;
  // camera_link and the optical frame, both in the YAML; the URDF chains them.
  const std::string yaml = io::read_text_file(folder / "camera.yaml");
  EXPECT_THAT(yaml, HasSubstr("  camera:"));
  EXPECT_THAT(yaml, HasSubstr("  camera_optical_frame:"));
  EXPECT_THAT(
      io::read_text_file(folder / "camera.urdf"),
      HasSubstr("<parent link=\"camera\"/>\n  <child link=\"camera_optical_frame\"/>\n  "
                "<origin xyz=\"0 0 0\" rpy=\"-1.5707963267948966 0 -1.5707963267948966\"/>"));

  // --camera-index picks a KITTI camera; for a simulator's folder and ROS intrinsics it picks
  // nothing, and says so (it was silent).
  const CliRun indexed = run_x2car("calibrate camera --input " + folder.string() +
                                   " --window-frames 12 --camera-index 3 --without-series");
  EXPECT_EQ(indexed.exit_code, 0) << indexed.output;
  EXPECT_THAT(indexed.output, HasSubstr("--camera-index 3 is unused"));
  EXPECT_THAT(calibrate.output, Not(HasSubstr("is unused")));

  // A mask whose black rows (the bottom 40) are left out: the same mounting, the share said.
  cv::Mat mask(375, 1242, CV_8U, cv::Scalar(255));
  mask.rowRange(335, 375).setTo(0);
  cv::imwrite((folder / "mask.png").string(), mask);
  const auto masked_json = folder / "masked.json";
  const CliRun masked =
      run_x2car("calibrate camera --input " + folder.string() + " --window-frames 12 --mask " +
                (folder / "mask.png").string() + " --without-series --out " + masked_json.string());
  ASSERT_EQ(masked.exit_code, 0) << masked.output;
  const std::string masked_result = io::read_text_file(masked_json);
  EXPECT_NEAR(number_after(masked_result, "", "\"ignored_region_share\""), 40.0 / 375.0, 1e-9);
  EXPECT_NEAR(number_after(masked_result, "", "\"pitch_deg\""), 0.05 * kDegPerRad, 0.1);

  // The paper's 100-frame window needs more than 24 frames: exit 1 with the reason.
  const CliRun few = run_x2car("calibrate camera --input " + folder.string());
  EXPECT_EQ(few.exit_code, 1) << few.output;
  EXPECT_THAT(few.output, HasSubstr("only 24 frames in stable stretches; need 100"));
}

// --ins gates frames by the car's motion: a log that turns throughout leaves no frame to use.
TEST(CalibrateCamera, InsLogGatesTurningFrames) {
  const auto folder = write_camera_drive("cli_calibrate_camera_ins", 24);
  const auto turning_log = [](double start_s) {
    std::string text = "time,x,y,z,vx,vy,vz,roll,pitch,yaw\n";
    for (int i = 0; i <= 400; ++i) {
      text += std::to_string(start_s + 0.01 * i) + "," + std::to_string(10.0 * i * 0.01) +
              ",0,0,10,0,0,0,0," + std::to_string(0.3 * 0.01 * i) + "\n";
    }
    return text;
  };
  const std::string ins = turning_log(9.0);
  const auto log = write_temp_file("cli_calibrate_camera_ins.csv", ins);
  const CliRun gated =
      run_x2car("calibrate camera --input " + folder.string() + " --window-frames 12 --ins " +
                log.string() + " --out " + (folder / "result.json").string());
  EXPECT_EQ(gated.exit_code, 1) << gated.output;
  EXPECT_THAT(gated.output, HasSubstr("24 of 24 frames covered"));
  EXPECT_THAT(io::read_text_file(folder / "result.json"), HasSubstr("\"turning\": 24"));
  // The summary says why too, though no angle was estimated (it printed the reason alone).
  EXPECT_THAT(gated.output, HasSubstr("rejected: turning 24"));
  // A log on another clock covers none of the frames: exit 2 with both spans (before: "another
  // clock?" alone).
  const auto later = write_temp_file("cli_calibrate_camera_ins_later.csv", turning_log(100.0));
  const CliRun other_clock = run_x2car("calibrate camera --input " + folder.string() +
                                       " --window-frames 12 --ins " + later.string());
  EXPECT_EQ(other_clock.exit_code, 2) << other_clock.output;
  EXPECT_THAT(other_clock.output, ContainsRegex("its records run 100.000-104.000 s, the frames "
                                                "10.000-[0-9.]+ s \\(another clock\\?\\)"));
  // A drive folder gives its log, as to calibrate ins (it was read as a KITTI OXTS folder).
  std::filesystem::copy_file(log, folder / "gnss.csv");
  io::write_text_file(folder / "x2car.yaml", "sensors:\n  gnss: {type: ins, input: gnss.csv}\n");
  const CliRun from_folder =
      run_x2car("calibrate camera --input " + folder.string() + " --window-frames 12 --ins " +
                folder.string() + " --out " + (folder / "from_folder.json").string());
  EXPECT_EQ(from_folder.exit_code, 1) << from_folder.output;
  EXPECT_THAT(from_folder.output, HasSubstr("24 of 24 frames covered"));
  // The log found in the folder is an input: no output may write over it.
  const CliRun over_log =
      run_x2car("calibrate camera --input " + folder.string() + " --window-frames 12 --ins " +
                folder.string() + " --out " + (folder / "gnss.csv").string());
  EXPECT_EQ(over_log.exit_code, 2) << over_log.output;
  EXPECT_EQ(io::read_text_file(folder / "gnss.csv"), ins);
}

// A video file is an input like a folder of images: the drive's frames as a Motion-JPEG AVI,
// times from its frame rate, intrinsics beside it.
TEST(CalibrateCamera, RecoversTheMountingFromAVideoFile) {
  const auto folder = write_camera_drive("cli_calibrate_camera_video", 24);
  // Motion-JPEG keeps an even height: the frames get a 376th row, and so do the intrinsics beside
  // the video.
  std::filesystem::create_directories(folder / "video");
  const auto video = folder / "video" / "drive.avi";
  core::CameraIntrinsics intrinsics =
      io::read_camera_info_yaml(folder / "camera" / "intrinsics.yaml");
  intrinsics.height += intrinsics.height % 2;
  io::write_camera_info_yaml(folder / "video" / "intrinsics.yaml", intrinsics);
  cv::VideoWriter writer(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0,
                         cv::Size(intrinsics.width, intrinsics.height), false);
  ASSERT_TRUE(writer.isOpened());
  for (int i = 0; i < 24; ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "%010d.png", i);
    cv::Mat frame =
        cv::imread((folder / "camera" / "images" / file).string(), cv::IMREAD_GRAYSCALE);
    cv::copyMakeBorder(frame, frame, 0, intrinsics.height - frame.rows, 0, 0, cv::BORDER_REPLICATE);
    writer.write(frame);
  }
  writer.release();
  const auto json = folder / "video_result.json";
  const CliRun calibrate = run_x2car("calibrate camera --input " + video.string() +
                                     " --window-frames 12 --without-series --out " + json.string());
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  EXPECT_THAT(calibrate.output, HasSubstr("found 24 frames"));
  EXPECT_THAT(calibrate.output, HasSubstr("video/intrinsics.yaml"));
  const std::string result = io::read_text_file(json);
  constexpr double kDegPerRad = 180.0 / M_PI;
  EXPECT_NEAR(number_after(result, "", "\"pitch_deg\""), 0.05 * kDegPerRad, 0.1) << result;
  EXPECT_NEAR(number_after(result, "", "\"yaw_deg\""), -0.03 * kDegPerRad, 0.1) << result;

  // --timestamps belongs to a video; a folder given with it is a usage error.
  const CliRun misused =
      run_x2car("calibrate camera --input " + folder.string() + " --timestamps " +
                (folder / "camera" / "timestamps.txt").string());
  EXPECT_EQ(misused.exit_code, 2) << misused.output;
  EXPECT_THAT(misused.output, HasSubstr("--timestamps"));
  // The video's times and rate are said; --frame-rate with --timestamps is a usage error (the
  // rate was silently ignored).
  EXPECT_THAT(calibrate.output, HasSubstr("10 frames/s; times from the video's frame times"));
  const CliRun both = run_x2car("calibrate camera --input " + video.string() + " --timestamps " +
                                (folder / "camera" / "timestamps.txt").string() +
                                " --frame-rate 10 --window-frames 12");
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_THAT(both.output, HasSubstr("give one"));
  // The motion estimator on a scene that does not move: exit 1, the reasons counted.
  const CliRun motion = run_x2car("calibrate camera --input " + folder.string() +
                                  " --estimator motion --window-frames 12 --out " +
                                  (folder / "motion.json").string());
  EXPECT_EQ(motion.exit_code, 1) << motion.output;
  EXPECT_THAT(io::read_text_file(folder / "motion.json"), HasSubstr("\"no_previous_frame\": 1"));
}

// A KITTI raw day: day/calib_cam_to_cam.txt beside day/drive/image_03/ (camera 3 the only one).
// The files x2car finds there, outside the --input folder, are inputs as much as those it is
// given, and camera 3's images take camera 3's keys.
TEST(CalibrateCamera, NeverWritesOverTheFilesItReadsAndReadsTheCamerasOwnKeys) {
  namespace fs = std::filesystem;
  const auto folder = write_camera_drive("cli_calibrate_camera_kitti_day", 24);
  const fs::path day = folder / "day";
  const fs::path drive = day / "drive_0001_sync";
  fs::create_directories(drive / "image_03");
  fs::copy(folder / "camera" / "images", drive / "image_03" / "data");
  fs::copy_file(folder / "camera" / "timestamps.txt", drive / "image_03" / "timestamps.txt");
  core::CameraIntrinsics camera_3 = core::camera_preset("kitti");
  core::CameraIntrinsics camera_2 = camera_3;
  camera_2.fx *= 1.2;  // another camera's keys would turn the angles
  camera_2.fy *= 1.2;
  const fs::path calib = day / "calib_cam_to_cam.txt";
  io::write_text_file(calib, io::format_kitti_calib_cam(camera_2, 2, "09-Jan-2012 13:57:47") +
                                 io::format_kitti_calib_cam(camera_3, 3, "09-Jan-2012 13:57:47"));
  const std::string calib_text = io::read_text_file(calib);
  const auto timestamps = drive / "image_03" / "timestamps.txt";
  const std::string timestamps_text = io::read_text_file(timestamps);
  const auto expect_refused = [](const CliRun& run, const fs::path& input,
                                 const std::string& text) {
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_THAT(run.output, HasSubstr("x2car never writes over the data it reads"));
    EXPECT_EQ(io::read_text_file(input), text) << input;
  };
  // The day's calibration, found above the drive.
  expect_refused(run_x2car("calibrate camera --input " + drive.string() +
                           " --window-frames 12 --out " + calib.string()),
                 calib, calib_text);
  // The timestamps above the data folder.
  expect_refused(run_x2car("calibrate camera --input " + (drive / "image_03" / "data").string() +
                           " --intrinsics " + calib.string() + " --window-frames 12 --urdf " +
                           timestamps.string()),
                 timestamps, timestamps_text);
  // Files given with --intrinsics and --mask.
  const fs::path intrinsics = folder / "camera" / "intrinsics.yaml";
  const std::string intrinsics_text = io::read_text_file(intrinsics);
  expect_refused(
      run_x2car("calibrate camera --input " + drive.string() + " --intrinsics " +
                intrinsics.string() + " --window-frames 12 --yaml " + intrinsics.string()),
      intrinsics, intrinsics_text);
  cv::imwrite((folder / "mask.png").string(), cv::Mat(375, 1242, CV_8U, cv::Scalar(255)));
  const std::string mask_bytes = io::read_text_file(folder / "mask.png");
  expect_refused(run_x2car("calibrate camera --input " + drive.string() + " --mask " +
                           (folder / "mask.png").string() + " --window-frames 12 --out " +
                           (folder / "mask.png").string()),
                 folder / "mask.png", mask_bytes);

  // Camera 3's keys: the true mounting (camera 2's focal length would tilt pitch and yaw).
  const auto json = folder / "kitti_day.json";
  const CliRun calibrate = run_x2car("calibrate camera --input " + drive.string() +
                                     " --window-frames 12 --without-series --out " + json.string());
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  EXPECT_THAT(calibrate.output, HasSubstr("intrinsics from " + calib.string()));
  const std::string result = io::read_text_file(json);
  constexpr double kDegPerRad = 180.0 / M_PI;
  EXPECT_NEAR(number_after(result, "", "\"pitch_deg\""), 0.05 * kDegPerRad, 0.1) << result;
  EXPECT_NEAR(number_after(result, "", "\"yaw_deg\""), -0.03 * kDegPerRad, 0.1) << result;
  // Asked for camera 2's keys for the folder of camera 3: refused, naming the folder.
  const CliRun other = run_x2car("calibrate camera --input " + (drive / "image_03").string() +
                                 " --camera-index 2 --intrinsics " + calib.string());
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_THAT(other.output, HasSubstr("holds KITTI camera 3's images (image_03), not camera 2's"));
}

TEST(CalibrateCamera, BadInputExitsWithTwoNamingTheFile) {
  const auto folder = write_camera_drive("cli_calibrate_camera_bad", 2);
  // Intrinsics of another image size.
  core::CameraIntrinsics other = core::camera_preset("automotive_1080p");
  io::write_camera_info_yaml(folder / "other.yaml", other);
  const CliRun size = run_x2car("calibrate camera --input " + folder.string() + " --intrinsics " +
                                (folder / "other.yaml").string());
  EXPECT_EQ(size.exit_code, 2) << size.output;
  EXPECT_THAT(size.output, HasSubstr("0000000000.png"));
  EXPECT_THAT(size.output, HasSubstr("image size"));
  // A mask of another size, or none at all.
  cv::imwrite((folder / "small_mask.png").string(), cv::Mat(100, 200, CV_8U, cv::Scalar(255)));
  const CliRun small_mask = run_x2car("calibrate camera --input " + folder.string() + " --mask " +
                                      (folder / "small_mask.png").string());
  EXPECT_EQ(small_mask.exit_code, 2) << small_mask.output;
  EXPECT_THAT(small_mask.output, HasSubstr("small_mask.png"));
  EXPECT_THAT(small_mask.output, HasSubstr("the mask is 200x100 pixels"));
  const CliRun no_mask = run_x2car("calibrate camera --input " + folder.string() + " --mask " +
                                   (folder / "absent.png").string());
  EXPECT_EQ(no_mask.exit_code, 2) << no_mask.output;
  EXPECT_THAT(no_mask.output, HasSubstr("absent.png"));
  // The network sees whole images: a mask is a usage error there, said before the file is read.
  cv::imwrite((folder / "mask.png").string(), cv::Mat(375, 1242, CV_8U, cv::Scalar(255)));
  for (const char* mask : {"mask.png", "absent.png"}) {
    const CliRun learned_mask =
        run_x2car("calibrate camera --input " + folder.string() + " --estimator learned --mask " +
                  (folder / mask).string());
    EXPECT_EQ(learned_mask.exit_code, 2) << learned_mask.output;
    EXPECT_THAT(learned_mask.output, HasSubstr("--mask is for the geometric, motion and auto"));
  }
  // A broken image.
  io::write_text_file(folder / "camera" / "images" / "0000000001.png", "not a png");
  const CliRun broken = run_x2car("calibrate camera --input " + folder.string());
  EXPECT_EQ(broken.exit_code, 2) << broken.output;
  EXPECT_THAT(broken.output, HasSubstr("0000000001.png"));
  // No intrinsics.
  std::filesystem::remove(folder / "camera" / "intrinsics.yaml");
  const CliRun missing = run_x2car("calibrate camera --input " + folder.string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("give --intrinsics"));
}

// calibrate all: every sensor of a simulated drive by its own command, one JSON keyed by sensor
// whose parts are the single commands' results, and the YAML and URDF of every sensor.
TEST(CalibrateAll, EverySensorAsItsOwnCommandGives) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all";
  std::filesystem::remove_all(folder);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 40 --seed 4 --sensors ins,radar "
                      "--out " +
                      folder.string())
                .exit_code,
            0);
  const auto all_json = folder / "all.json";
  const CliRun all =
      run_x2car("calibrate all --input " + folder.string() +
                " --reproducible --without-series --out " + all_json.string() + " --yaml " +
                (folder / "all.yaml").string() + " --urdf " + (folder / "all.urdf").string());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  // The table against the truth: each estimated angle with its error in parentheses.
  EXPECT_THAT(all.output, HasSubstr("(in parentheses: the error against ground_truth.yaml)"));
  EXPECT_THAT(all.output, ::testing::ContainsRegex("radar +ok .*\\([-+]0\\.0"));
  // The sensors ran side by side; each one's summary follows its own heading, in order.
  const std::size_t ins_heading = all.output.find("== ins (ins,");
  const std::size_t radar_heading = all.output.find("== radar (radar,");
  ASSERT_NE(ins_heading, std::string::npos) << all.output;
  ASSERT_NE(radar_heading, std::string::npos) << all.output;
  EXPECT_LT(ins_heading, all.output.find("ins: vehicle_from_ins"));
  EXPECT_LT(all.output.find("ins: vehicle_from_ins"), radar_heading);
  EXPECT_LT(radar_heading, all.output.find("radar: vehicle_from_radar"));

  const CliRun radar =
      run_x2car("calibrate radar --input " + (folder / "radar").string() + " --ins " +
                (folder / "ins" / "novatel_enu.csv").string() +
                " --reproducible --without-series --out " + (folder / "radar.json").string());
  ASSERT_EQ(radar.exit_code, 0) << radar.output;
  const auto combined = io::Json::parse(io::read_text_file(all_json));
  EXPECT_EQ(combined.at("radar").dump(2),
            io::Json::parse(io::read_text_file(folder / "radar.json")).dump(2));
  EXPECT_EQ(combined.at("ins").at("status"), "ok");
  const std::string yaml = io::read_text_file(folder / "all.yaml");
  EXPECT_THAT(yaml, HasSubstr("  ins:"));
  EXPECT_THAT(yaml, HasSubstr("  radar:"));
  EXPECT_THAT(io::read_text_file(folder / "all.urdf"), HasSubstr("<child link=\"radar\"/>"));

  // convert reads the file back: the sensor picked by --child, into every form.
  const CliRun convert =
      run_x2car("convert --input " + all_json.string() + " --child radar --to all");
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  EXPECT_THAT(convert.output, HasSubstr("base_link from radar"));
  EXPECT_THAT(convert.output, HasSubstr("autoware:"));
  const CliRun which = run_x2car("convert --input " + all_json.string());
  EXPECT_EQ(which.exit_code, 2) << which.output;
  EXPECT_THAT(which.output, HasSubstr("pick one with --child"));
}

// The route into a user's stack (issue 16 item 5): calibrate all's results merged into their
// sensor kit file keep every translation and every angle x2car did not estimate, as written.
TEST(CalibrateAll, ResultsMergeIntoAnAutowareFileAndAReport) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_merge";
  std::filesystem::remove_all(folder);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 40 --seed 6 --sensors ins,radar "
                      "--out " +
                      folder.string())
                .exit_code,
            0);
  const auto all_json = folder / "all.json";
  ASSERT_EQ(run_x2car("calibrate all --input " + folder.string() + " --out " + all_json.string() +
                      " --report " + (folder / "all.html").string())
                .exit_code,
            0);
  const std::string kit =
      "# sensor kit of car 7\n"
      "base_link:\n"
      "  ins: {x: 1.25, y: -0.3, z: 1.1, roll: 0.00400, pitch: 0.0, yaw: 0.0}\n"
      "  radar: {x: 3.6, y: 0.1, z: 0.5, roll: 0.0010, pitch: -2e-3, yaw: 0.0}\n"
      "  camera_link: {x: 1.9, y: 0.0, z: 1.4, roll: 0.0, pitch: 0.05, yaw: 0.0}\n";
  const auto kit_path = write_temp_file("cli_merge_kit.yaml", kit);
  const auto merged_path = folder / "merged.yaml";
  const CliRun merge = run_x2car("convert --input " + all_json.string() + " --merge-into " +
                                 kit_path.string() + " --out " + merged_path.string());
  ASSERT_EQ(merge.exit_code, 0) << merge.output;
  EXPECT_THAT(merge.output, HasSubstr("before -> after"));
  EXPECT_THAT(merge.output, HasSubstr("kept (not estimated)"));
  const std::string merged = io::read_text_file(merged_path);
  const auto combined = io::Json::parse(io::read_text_file(all_json));
  // The radar's yaw and the GNSS/INS's pitch and yaw are replaced; all else is as written.
  const std::string radar_yaw =
      io::format_number(combined.at("radar").at("yaw_deg").get<double>() * M_PI / 180.0);
  EXPECT_THAT(merged, HasSubstr("  radar: {x: 3.6, y: 0.1, z: 0.5, roll: 0.0010, pitch: -2e-3, "
                                "yaw: " +
                                radar_yaw.substr(0, 8)));
  EXPECT_THAT(merged, HasSubstr("  ins: {x: 1.25, y: -0.3, z: 1.1, roll: 0.00400, pitch: "));
  EXPECT_THAT(merged, HasSubstr("# sensor kit of car 7\n"));
  EXPECT_THAT(
      merged,
      HasSubstr("  camera_link: {x: 1.9, y: 0.0, z: 1.4, roll: 0.0, pitch: 0.05, yaw: 0.0}"));
  EXPECT_EQ(io::read_text_file(kit_path), kit);  // the user's file is never changed
  // Writing over the file merged into is refused.
  const CliRun over = run_x2car("convert --input " + all_json.string() + " --merge-into " +
                                kit_path.string() + " --out " + kit_path.string());
  EXPECT_EQ(over.exit_code, 2) << over.output;

  // A prior in any form: its translation and the radar's roll and pitch kept, the yaw replaced.
  const auto prior = write_temp_file("cli_merge_prior.txt", "3.6 0.1 0.5 0.2 -0.1 7\n");
  const CliRun with_prior =
      run_x2car("convert --input " + all_json.string() + " --child radar --prior " +
                prior.string() + " --prior-from xyzrpy-deg --to xyzrpy-deg");
  ASSERT_EQ(with_prior.exit_code, 0) << with_prior.output;
  // The mounting is the last line, after the before -> after table.
  std::string printed = with_prior.output;
  while (!printed.empty() && printed.back() == '\n') printed.pop_back();
  const std::vector<double> merged_numbers =
      numbers_in(printed.substr(printed.find_last_of('\n') + 1));
  ASSERT_EQ(merged_numbers.size(), 6U) << with_prior.output;
  EXPECT_NEAR(merged_numbers[0], 3.6, 1e-12);
  EXPECT_NEAR(merged_numbers[3], 0.2, 1e-9);
  EXPECT_NEAR(merged_numbers[4], -0.1, 1e-9);
  EXPECT_NEAR(merged_numbers[5], combined.at("radar").at("yaw_deg").get<double>(), 1e-9);

  // convert takes the result to every form and back: the same mounting (yaw estimated, the rest 0).
  const double yaw = combined.at("radar").at("yaw_deg").get<double>() * M_PI / 180.0;
  for (const char* form :
       {"xyzrpy-deg", "xyzrpy-rad", "matrix", "quaternion", "urdf", "autoware", "reference"}) {
    const auto written = folder / (std::string("radar.") + form);
    ASSERT_EQ(run_x2car("convert --input " + all_json.string() + " --child radar --to " + form +
                        " --out " + written.string())
                  .exit_code,
              0)
        << form;
    const CliRun back = run_x2car("convert --input " + written.string() + " --from " + form +
                                  " --child radar --to xyzrpy-rad");
    ASSERT_EQ(back.exit_code, 0) << form << ": " << back.output;
    const std::vector<double> numbers = numbers_in(back.output);
    ASSERT_EQ(numbers.size(), 6U) << form << ": " << back.output;
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(numbers[i], 0.0, 1e-12) << form << " value " << i;
    EXPECT_NEAR(numbers[5], yaw, 1e-12) << form;
  }

  // The report of the same results, from the files.
  const auto html = folder / "again.html";
  const CliRun report = run_x2car("report --result " + all_json.string() + " --input " +
                                  folder.string() + " --out " + html.string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string page = io::read_text_file(html);
  EXPECT_THAT(page, HasSubstr("id=\"x2car-data\""));
  EXPECT_THAT(page, HasSubstr("\"truth\":{\"roll_deg\""));
  EXPECT_TRUE(std::filesystem::exists(folder / "all.html"));
  EXPECT_EQ(run_x2car("report --out " + html.string()).exit_code, 2);
  const CliRun missing = run_x2car("report --result /no/such.json --out " + html.string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.output, HasSubstr("/no/such.json"));
  EXPECT_EQ(
      run_x2car("report --result " + all_json.string() + " --out " + all_json.string()).exit_code,
      2);
}

// calibrate ins finds the log in a drive folder (issue 17 item 5): the same result as given the
// file.
TEST(CalibrateIns, FindsTheLogInADriveFolder) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_ins_drive_folder";
  std::filesystem::remove_all(folder);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 30 --seed 8 --out " + folder.string())
                .exit_code,
            0);
  const auto from_folder = folder / "from_folder.json";
  const auto from_file = folder / "from_file.json";
  ASSERT_EQ(run_x2car("calibrate ins --input " + folder.string() + " --reproducible --out " +
                      from_folder.string())
                .exit_code,
            0);
  ASSERT_EQ(run_x2car("calibrate ins --input " + (folder / "ins" / "novatel_enu.csv").string() +
                      " --reproducible --out " + from_file.string())
                .exit_code,
            0);
  EXPECT_EQ(io::read_text_file(from_folder), io::read_text_file(from_file));
  // The log a manifest names outside its folder is an input too: an output that is it was
  // written over before (only the folder was checked).
  const auto manifest_drive = folder / "manifest_drive";
  std::filesystem::create_directories(manifest_drive);
  io::write_text_file(manifest_drive / "x2car.yaml",
                      "sensors:\n  gnss: {type: ins, input: ../ins/novatel_enu.csv}\n");
  const auto log = folder / "ins" / "novatel_enu.csv";
  const std::string log_text = io::read_text_file(log);
  const CliRun over_log =
      run_x2car("calibrate ins --input " + manifest_drive.string() + " --out " + log.string());
  EXPECT_EQ(over_log.exit_code, 2) << over_log.output;
  EXPECT_THAT(over_log.output, HasSubstr("never writes over the data it reads"));
  EXPECT_EQ(io::read_text_file(log), log_text);
  // A folder where no file can be made (as root, access() lets /proc pass): not "No such file".
  const CliRun into_proc =
      run_x2car("calibrate ins --input " + log.string() + " --out /proc/x2car.json");
  EXPECT_EQ(into_proc.exit_code, 2) << into_proc.output;
  EXPECT_THAT(into_proc.output, HasSubstr("the folder /proc is not writable"));
  EXPECT_THAT(into_proc.output, Not(HasSubstr("No such file")));
  // A vendor's header read through --columns: the same result as x2car's own names.
  std::string csv = io::read_text_file(folder / "ins" / "ins.csv");
  const std::string header = "time,x,y,z,vx,vy,vz,roll,pitch,yaw\n";
  ASSERT_EQ(csv.rfind(header, 0), 0U);
  csv.replace(0, header.size(), "GPS Time,E,N,U,VE,VN,VU,R,P,Yaw Angle\n");
  io::write_text_file(folder / "vendor.csv", csv);
  const auto from_ins_csv = folder / "from_ins_csv.json";
  const auto from_vendor = folder / "from_vendor.json";
  ASSERT_EQ(run_x2car("calibrate ins --input " + (folder / "ins" / "ins.csv").string() +
                      " --reproducible --out " + from_ins_csv.string())
                .exit_code,
            0);
  const CliRun vendor = run_x2car(
      "calibrate ins --input " + (folder / "vendor.csv").string() +
      " --columns 'time=GPS Time,east=E,north=N,up=U,ve=VE,vn=VN,vu=VU,roll=R,pitch=P,yaw=Yaw "
      "Angle' --reproducible --out " +
      from_vendor.string());
  ASSERT_EQ(vendor.exit_code, 0) << vendor.output;
  EXPECT_EQ(io::read_text_file(from_vendor), io::read_text_file(from_ins_csv));
  const CliRun bad =
      run_x2car("calibrate ins --input " + (folder / "vendor.csv").string() + " --columns speed=V");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("'speed' is not a column x2car reads"));

  std::filesystem::remove(folder / "ins" / "novatel_enu.csv");
  const CliRun missing = run_x2car("calibrate ins --input " + folder.string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("novatel_enu.csv"));
}

// A user's own layout: x2car.yaml names each sensor's type, input and options.
TEST(CalibrateAll, AManifestDescribesAUsersLayout) {
  const auto drive =
      std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_manifest_drive";
  std::filesystem::remove_all(drive);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 40 --seed 7 --sensors ins,radar_left "
                      "--out " +
                      drive.string())
                .exit_code,
            0);
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_manifest";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder / "logs");
  std::filesystem::copy_file(drive / "ins" / "novatel_enu.csv", folder / "logs" / "gnss.csv");
  std::filesystem::copy(drive / "radar_left", folder / "logs" / "left",
                        std::filesystem::copy_options::recursive);
  const std::string truth = io::read_text_file(drive / "ground_truth.yaml");
  const double x = number_after(truth, "vehicle_from_radar_left:", "x");
  const double y = number_after(truth, "vehicle_from_radar_left:", "y");
  io::write_text_file(folder / "x2car.yaml",
                      "sensors:\n  gnss: {type: ins, input: logs/gnss.csv}\n  left: {type: radar, "
                      "input: logs/left, lever_arm: [" +
                          std::to_string(x) + ", " + std::to_string(y) +
                          "], nominal_yaw_deg: 90}\n");
  const auto json = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_manifest.json";
  const CliRun run =
      run_x2car("calibrate all --input " + folder.string() + " --out " + json.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto result = io::Json::parse(io::read_text_file(json));
  EXPECT_EQ(result.at("gnss").at("status"), "ok");
  const double true_yaw_deg = number_after(truth, "vehicle_from_radar_left:", "yaw") * 180.0 / M_PI;
  EXPECT_NEAR(result.at("left").at("yaw_deg").get<double>(), true_yaw_deg, 0.2);

  // The manifest's options reach the radar's command: without the lever arm its turns are gated
  // out (fewer detections used), and a prior 180 deg off keeps the velocity method's search in a
  // basin where its fit fails its checks.
  io::write_text_file(folder / "x2car.yaml",
                      "sensors:\n  gnss: {type: ins, input: logs/gnss.csv}\n  left: {type: radar, "
                      "input: logs/left, nominal_yaw_deg: -90}\n");
  const auto other =
      std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_manifest_2.json";
  ASSERT_EQ(
      run_x2car("calibrate all --input " + folder.string() + " --out " + other.string()).exit_code,
      0);
  const auto without_lever = io::Json::parse(io::read_text_file(other));
  EXPECT_LT(without_lever.at("left").at("support").at("velocity_detections").get<int>(),
            result.at("left").at("support").at("velocity_detections").get<int>());
  EXPECT_THAT(without_lever.at("left").at("reason").get<std::string>(),
              HasSubstr("velocity method, unreliable"));

  // A wrong path names its key.
  io::write_text_file(folder / "x2car.yaml", "sensors:\n  gnss: {type: ins, input: gnss.csv}\n");
  const CliRun bad = run_x2car("calibrate all --input " + folder.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("sensors.gnss.input"));
}

// A sensor with too little data: exit 1, and the others are still written.
TEST(CalibrateAll, PartialSuccessExitsWithOneAndWritesTheRest) {
  const auto folder = write_camera_drive("cli_calibrate_all_partial", 24);
  const auto ins_drive = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_ins";
  std::filesystem::remove_all(ins_drive);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 60 --seed 5 --sensors ins --out " +
                      ins_drive.string())
                .exit_code,
            0);
  std::filesystem::create_directories(folder / "ins");
  std::filesystem::copy_file(ins_drive / "ins" / "novatel_enu.csv",
                             folder / "ins" / "novatel_enu.csv");
  const CliRun run =
      run_x2car("calibrate all --input " + folder.string() + " --out " +
                (folder / "all.json").string() + " --yaml " + (folder / "all.yaml").string());
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const auto combined = io::Json::parse(io::read_text_file(folder / "all.json"));
  EXPECT_EQ(combined.at("ins").at("status"), "ok");
  EXPECT_EQ(combined.at("camera").at("status"), "insufficient_data");
  const std::string yaml = io::read_text_file(folder / "all.yaml");
  EXPECT_THAT(yaml, HasSubstr("  ins:"));
  EXPECT_THAT(yaml, Not(HasSubstr("  camera:")));

  // No sensor calibrated: exit 1, the JSON written, no YAML (there is no mounting to write).
  std::filesystem::remove_all(folder / "ins");
  std::filesystem::remove(folder / "all.yaml");
  const CliRun none =
      run_x2car("calibrate all --input " + folder.string() + " --out " +
                (folder / "none.json").string() + " --yaml " + (folder / "all.yaml").string());
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_THAT(none.output, HasSubstr("no sensor calibrated"));
  EXPECT_FALSE(std::filesystem::exists(folder / "all.yaml"));
}

TEST(CalibrateAll, BadFoldersExitWithTwoNamingThePath) {
  const auto empty = std::filesystem::path(::testing::TempDir()) / "cli_calibrate_all_empty";
  std::filesystem::remove_all(empty);
  std::filesystem::create_directories(empty / "notes");
  const CliRun none = run_x2car("calibrate all --input " + empty.string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_THAT(none.output, HasSubstr("holds no sensor folder"));
  // A radar without the car's motion.
  std::filesystem::create_directories(empty / "radar_left");
  const CliRun radar = run_x2car("calibrate all --input " + empty.string());
  EXPECT_EQ(radar.exit_code, 2) << radar.output;
  EXPECT_THAT(radar.output, HasSubstr("radar_left"));
  EXPECT_THAT(radar.output, HasSubstr("no ins/novatel_enu.csv"));
}

// eval: the paper's protocol on a simulated drive: the whole log and each minute, their spread,
// the errors against the truth; a sensor the folder lacks is an input error naming it.
TEST(Eval, SegmentsOfAMinuteAgainstTheTruth) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_eval";
  std::filesystem::remove_all(folder);
  ASSERT_EQ(run_x2car("simulate --scenario urban --duration 130 --seed 6 --sensors ins,radar "
                      "--out " +
                      folder.string())
                .exit_code,
            0);
  const auto json = std::filesystem::path(::testing::TempDir()) / "cli_eval.json";
  const CliRun eval = run_x2car("eval --input " + folder.string() + " --out " + json.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_THAT(eval.output, HasSubstr("== ins: 2 segments"));
  EXPECT_THAT(eval.output, HasSubstr("== radar: 2 segments"));
  EXPECT_THAT(eval.output, HasSubstr("(error: the whole log's estimate minus ground_truth.yaml)"));
  const auto result = io::Json::parse(io::read_text_file(json));
  ASSERT_EQ(result.at("radar").at("segments").size(), 2U);  // 60 + 60; the last 10 s dropped
  EXPECT_EQ(result.at("radar").at("segments").at(1).at("start_s").get<double>() -
                result.at("radar").at("segments").at(0).at("start_s").get<double>(),
            60.0);
  // Each minute's radar yaw is within 0.2 deg of the truth (the whole log's is the bench's).
  const std::string truth = io::read_text_file(folder / "ground_truth.yaml");
  const double true_yaw_deg = number_after(truth, "vehicle_from_radar:", "yaw") * 180.0 / M_PI;
  for (const auto& segment : result.at("radar").at("segments")) {
    ASSERT_EQ(segment.at("result").at("status"), "ok") << segment.dump();
    EXPECT_NEAR(segment.at("result").at("yaw_deg").get<double>(), true_yaw_deg, 0.2);
  }
  EXPECT_EQ(result.at("ins").at("summary").at("with_estimate"), 2);

  const CliRun one = run_x2car("eval --input " + folder.string() + " --sensor ins --segment 40");
  EXPECT_EQ(one.exit_code, 0) << one.output;
  EXPECT_THAT(one.output, HasSubstr("== ins: 3 segments"));
  EXPECT_THAT(one.output, Not(HasSubstr("== radar")));
  const CliRun missing = run_x2car("eval --input " + folder.string() + " --sensor lidar");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("no sensor 'lidar'; the folder holds: ins, radar"));

  // A camera's segments: 24 frames (10 to 12.3 s) in segments of a second, each too short for the
  // paper's window: counted, no estimate, exit 1 (its whole log has none either).
  const auto camera_drive = write_camera_drive("cli_eval_camera", 24);
  std::filesystem::copy(camera_drive / "camera", folder / "camera",
                        std::filesystem::copy_options::recursive);
  const CliRun camera =
      run_x2car("eval --input " + folder.string() + " --sensor camera --segment 1");
  EXPECT_EQ(camera.exit_code, 1) << camera.output;
  EXPECT_THAT(camera.output, HasSubstr("== camera: 2 segments, 0 gave an estimate"));
}

// The learned network from end to end (issue 15): trained on a short simulated drive, scored, and
// used by calibrate camera; its refusals exit 2 naming what is wrong. In a build without LibTorch
// every one of them exits 2 saying how to enable it.
TEST(CameraNet, TrainsScoresAndCalibratesAndRefusesWhatDoesNotFit) {
  const auto folder = std::filesystem::path(::testing::TempDir()) / "cli_camera_net";
  std::filesystem::remove_all(folder);
  const std::string drive = (folder / "drive").string();
  ASSERT_EQ(run_x2car("simulate --duration 3 --sensors camera --seed 5 --out " + drive).exit_code,
            0);
  const std::string model = (folder / "tiny.pt").string();
  const CliRun train = run_x2car(
      "camera-net train --size tiny --epochs 1 --stride 3 --data " + drive + " --out " + model,
      300);
  if (!camera_net::network_available()) {
    EXPECT_EQ(train.exit_code, 2) << train.output;
    EXPECT_THAT(train.output, HasSubstr("libtorch-dev"));
    const CliRun learned =
        run_x2car("calibrate camera --input " + drive + " --estimator learned --model " + model);
    EXPECT_EQ(learned.exit_code, 2) << learned.output;
    EXPECT_THAT(learned.output, HasSubstr("libtorch-dev"));
    return;
  }
  ASSERT_EQ(train.exit_code, 0) << train.output;
  EXPECT_THAT(train.output, HasSubstr("wrote " + model));
  EXPECT_THAT(train.output, HasSubstr("| this network (CPU) |"));

  const std::string metrics = (folder / "metrics.json").string();
  const CliRun eval =
      run_x2car("camera-net eval --data " + drive + " --model " + model + " --out " + metrics, 300);
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_THAT(eval.output, HasSubstr("paper, Table I"));
  const nlohmann::json scores = nlohmann::json::parse(io::read_text_file(metrics));
  EXPECT_EQ(scores.at("frames").get<int>(), 30);
  EXPECT_TRUE(std::isfinite(scores.at("vp_error_px_mean").get<double>()));

  // Through the temporal filter: 30 frames are too few for a window of 100 (exit 1 with the
  // reason), never a number.
  const CliRun learned =
      run_x2car("calibrate camera --input " + drive + " --estimator learned --model " + model);
  EXPECT_EQ(learned.exit_code, 1) << learned.output;
  EXPECT_THAT(learned.output, HasSubstr("need 100"));
  EXPECT_THAT(learned.output, Not(HasSubstr("nan")));

  // Without --model, the shipped network (models/camera_net_kitti.pt).
  const CliRun shipped = run_x2car("calibrate camera --input " + drive + " --estimator learned");
  EXPECT_EQ(shipped.exit_code, 1) << shipped.output;
  EXPECT_THAT(shipped.output, HasSubstr("camera_net_kitti.pt"));
  EXPECT_EQ(run_x2car("calibrate camera --input " + drive + " --model " + model).exit_code, 2);

  // A network trained on 1242x375 frames refuses a 1920x1080 camera, naming both.
  std::string intrinsics = io::read_text_file(drive + "/camera/intrinsics.yaml");
  intrinsics.replace(intrinsics.find("image_width: 1242"), 17, "image_width: 1920");
  intrinsics.replace(intrinsics.find("image_height: 375"), 17, "image_height: 1080");
  const auto wide = write_temp_file("cli_camera_net_1080p.yaml", intrinsics);
  const CliRun misfit =
      run_x2car("calibrate camera --input " + drive + " --estimator learned --model " + model +
                " --intrinsics " + wide.string());
  EXPECT_EQ(misfit.exit_code, 2) << misfit.output;
  EXPECT_THAT(misfit.output, HasSubstr("1242x375"));
  EXPECT_THAT(misfit.output, HasSubstr("1920x1080"));

  const auto not_a_model = write_temp_file("cli_camera_net_not_a_model.pt", "weights");
  const CliRun unreadable =
      run_x2car("camera-net eval --data " + drive + " --model " + not_a_model.string());
  EXPECT_EQ(unreadable.exit_code, 2);
  EXPECT_THAT(unreadable.output, HasSubstr("cli_camera_net_not_a_model.pt"));
}

}  // namespace
}  // namespace x2car::cli
