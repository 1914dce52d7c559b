#include "x2car/radar/radar_calibration.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/io/ins_log.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_velocity_method.hpp"
#include "x2car/sim/radar_model.hpp"
#include "x2car/sim/radar_scene.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

namespace testing = sim::testing;

using ::testing::HasSubstr;

using testing::kRadarLeverArm;
using testing::radar_detections;
using testing::RadarDrive;
using testing::urban_radar_drive;

double yaw_error_deg(std::uint64_t seed, double truth_deg, const sim::RadarOptions& radar,
                     const RadarCalibrationOptions& options) {
  const RadarDrive& drive = urban_radar_drive(seed);
  const auto detections = radar_detections(drive, truth_deg, radar, seed);
  const CalibrationResult result = calibrate_radar(detections, drive.simulation.ins, options);
  EXPECT_TRUE(result.ok()) << result.reason;
  if (!result.ok()) return NAN;
  EXPECT_FALSE(result.roll);
  EXPECT_FALSE(result.pitch);
  EXPECT_TRUE(result.yaw_std && std::isfinite(*result.yaw_std));
  EXPECT_EQ(result.method, "velocity");
  return deg_from_rad(angle_difference(*result.yaw, rad_from_deg(truth_deg)));
}

RadarCalibrationOptions velocity_method() {
  RadarCalibrationOptions options;
  options.method = RadarMethod::kVelocity;
  return options;
}

RadarCalibrationOptions with_lever_arm() {
  RadarCalibrationOptions options = velocity_method();
  options.lever_arm_in_vehicle = kRadarLeverArm.head<2>();
  return options;
}

// Issue 6: truth 0, 10, 20, -7 deg, urban 60 s, 5 seeds: velocity method |error| <= 0.1 deg.
// Measured: Conti within 0.057 deg, Delphi within 0.096 deg (fewer, noisier detections in a
// narrower field of view); every error is within 2.3 reported standard errors.
void expect_issue_accuracy(const sim::RadarOptions& radar, const RadarCalibrationOptions& options) {
  for (const double truth_deg : {0.0, 10.0, 20.0, -7.0}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      SCOPED_TRACE(::testing::Message() << "truth " << truth_deg << " deg, seed " << seed);
      EXPECT_LE(std::abs(yaw_error_deg(seed, truth_deg, radar, options)), 0.1);
    }
  }
}

TEST(RadarCalibration, VelocityContiMeetsATenthOfADegree) {
  expect_issue_accuracy(sim::RadarOptions::conti_ars408(), with_lever_arm());
}

TEST(RadarCalibration, VelocityDelphiMeetsATenthOfADegree) {
  expect_issue_accuracy(sim::RadarOptions::delphi_esr(), with_lever_arm());
}

// Without the lever arm, turns are gated out by the yaw rate.
TEST(RadarCalibration, VelocityWithoutLeverArmTurnsAreGatedOut) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    EXPECT_LE(
        std::abs(yaw_error_deg(seed, 10.0, sim::RadarOptions::conti_ars408(), velocity_method())),
        0.1);
  }
}

// The coarse search finds psi 30 deg away from the initial guess 0.
TEST(RadarCalibration, VelocityCoarseSearchRecoversThirtyDegrees) {
  const RadarDrive& drive = urban_radar_drive(2);
  const auto detections = radar_detections(drive, 30.0, sim::RadarOptions::conti_ars408(), 2);
  const CalibrationResult result =
      calibrate_radar(detections, drive.simulation.ins, with_lever_arm());
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(result.diagnostics.at("coarse_yaw_deg"), 30.0, 5.0);
  EXPECT_NEAR(deg_from_rad(*result.yaw), 30.0, 0.1);
}

// Sign: a radar yawed +10 deg (boresight turned left) reports +10, and a static target ahead-left
// while driving forward approaches (negative range rate) as the header states.
TEST(RadarCalibration, VelocitySignConvention) {
  RadarSample sample;
  sample.azimuth = rad_from_deg(20.0);
  sample.radar_velocity_in_vehicle = {10.0, 0.0};
  EXPECT_NEAR(static_range_rate(sample, rad_from_deg(10.0)), -10.0 * std::cos(rad_from_deg(30.0)),
              1e-12);
  const RadarDrive& drive = urban_radar_drive(1);
  const auto detections = radar_detections(drive, 10.0, sim::RadarOptions::conti_ars408(), 1);
  const CalibrationResult result =
      calibrate_radar(detections, drive.simulation.ins, with_lever_arm());
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(deg_from_rad(*result.yaw), 10.0, 0.1);
}

// The INS's mounting yaw is not known here and may be any: a box mounted backwards or sideways
// turns its heading by 180 or +-90 deg against the car's travel. The car still drives ahead in most
// of the drive, and the radar's yaw is the same (it was 180 deg off, `ok`, for every such
// mounting, by either method: the speed's sign came from the INS's x axis).
TEST(RadarCalibration, AnInsMountedBackwardsOrSidewaysGivesTheSameYaw) {
  const RadarDrive& drive = urban_radar_drive(1);
  const auto detections = radar_detections(drive, 10.0, sim::RadarOptions::conti_ars408(), 1);
  for (const double ins_yaw_deg : {180.0, 90.0, -90.0}) {
    std::vector<io::InsRecord> turned = drive.simulation.ins;
    for (io::InsRecord& record : turned) {
      record.attitude.yaw = wrap_angle(record.attitude.yaw + rad_from_deg(ins_yaw_deg));
    }
    for (const RadarMethod method : {RadarMethod::kVelocity, RadarMethod::kPosition}) {
      SCOPED_TRACE(::testing::Message()
                   << "INS yaw " << ins_yaw_deg << " deg, method " << to_string(method));
      RadarCalibrationOptions options = with_lever_arm();
      options.method = method;
      const CalibrationResult result = calibrate_radar(detections, turned, options);
      ASSERT_TRUE(result.ok()) << result.reason;
      EXPECT_NEAR(deg_from_rad(angle_difference(*result.yaw, rad_from_deg(10.0))), 0.0, 0.3);
    }
  }
}

// Through the files, as the CLI reads them: a Delphi scan folder and novatel_enu.csv, each with
// its own UTC time 0, aligned by radar_to_ins_time_offset.
TEST(RadarCalibration, DelphiFilesAndNovatelLogRoundTrip) {
  const RadarDrive& drive = urban_radar_drive(3);
  const auto detections = radar_detections(drive, -7.0, sim::RadarOptions::delphi_esr(), 3);
  const std::filesystem::path folder =
      std::filesystem::path(::testing::TempDir()) / "x2car_radar_calibration_round_trip";
  std::filesystem::remove_all(folder);
  io::write_radar(folder / "radar", io::RadarLayout::kDelphi, detections,
                  drive.simulation.start_unix_time);
  io::write_novatel_enu(folder / "novatel_enu.csv", drive.simulation.ins,
                        drive.simulation.start_unix_time + drive.simulation.ins.front().time);
  const io::RadarLog radar_log = io::read_radar(folder / "radar", io::RadarLayout::kDelphi);
  const io::InsLog ins_log = io::read_ins_log(folder / "novatel_enu.csv");
  std::vector<io::RadarDetection> read_back = radar_log.detections;
  const double offset_s =
      radar_to_ins_time_offset(radar_log.start_unix_time, ins_log.start_unix_time);
  for (io::RadarDetection& detection : read_back) detection.time += offset_s;
  const CalibrationResult result = calibrate_radar(read_back, ins_log.records, with_lever_arm());
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(deg_from_rad(*result.yaw), -7.0, 0.1);
  EXPECT_EQ(result.rejections.at("outside_ins_span"), 0);
}

TEST(RadarCalibration, CarThatNeverMovesIsInsufficientData) {
  const RadarDrive& drive = urban_radar_drive(1);
  const auto detections = radar_detections(drive, 5.0, sim::RadarOptions::conti_ars408(), 1);
  std::vector<io::InsRecord> standing(drive.simulation.ins.begin(), drive.simulation.ins.end());
  for (io::InsRecord& record : standing) {
    record.position_enu = standing.front().position_enu;
    record.velocity_enu.setZero();
    record.attitude = standing.front().attitude;
  }
  const CalibrationResult result = calibrate_radar(detections, standing);
  EXPECT_FALSE(result.ok());
  EXPECT_FALSE(result.yaw);
  EXPECT_THAT(result.reason, HasSubstr("fastest 0.0 m/s"));
  EXPECT_GT(result.rejections.at("slow"), 0);
}

TEST(RadarCalibration, DetectionsOutsideTheInsSpanAreCounted) {
  const RadarDrive& drive = urban_radar_drive(1);
  auto detections = radar_detections(drive, 5.0, sim::RadarOptions::conti_ars408(), 1);
  const double end = drive.simulation.ins.back().time;
  io::RadarDetection late = detections.back();
  for (int i = 0; i < 7; ++i) {
    late.time = end + 1.0 + i;
    detections.push_back(late);
  }
  const CalibrationResult result =
      calibrate_radar(detections, drive.simulation.ins, with_lever_arm());
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.rejections.at("outside_ins_span"), 7);
}

// Issue 11: a jump in the stamps of both logs; the result is that of the logs without it, and no
// detection is given a motion interpolated across the gap.
TEST(RadarCalibration, AMillionSecondJumpInTheStampsCalibratesAsWithoutIt) {
  const RadarDrive& drive = urban_radar_drive(1);
  const auto detections = radar_detections(drive, 5.0, sim::RadarOptions::conti_ars408(), 1);
  std::vector<io::InsRecord> ins = drive.simulation.ins;
  std::vector<io::RadarDetection> jumped = detections;
  const double jump_from = 30.0;
  for (io::InsRecord& record : ins) {
    if (record.time > jump_from) record.time += 1e6;
  }
  std::int64_t in_gap = 0;
  const double first_after = std::ranges::find_if(drive.simulation.ins, [&](const auto& record) {
                               return record.time > jump_from;
                             })->time;
  for (io::RadarDetection& detection : jumped) {
    if (detection.time > jump_from && detection.time < first_after) ++in_gap;
    if (detection.time > jump_from) detection.time += 1e6;
  }
  const CalibrationResult plain = calibrate_radar(detections, drive.simulation.ins);
  const CalibrationResult result = calibrate_radar(jumped, ins);
  ASSERT_TRUE(plain.ok()) << plain.reason;
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.method, plain.method);
  EXPECT_EQ(result.rejections.at("in_ins_gap"), in_gap);
  EXPECT_NEAR(deg_from_rad(angle_difference(*result.yaw, *plain.yaw)), 0.0, 0.02);
  EXPECT_NEAR(deg_from_rad(angle_difference(*result.yaw, rad_from_deg(5.0))), 0.0, 0.1);
}

TEST(RadarCalibration, ASparseInsLogSaysWhyTheDetectionsWereDropped) {
  const RadarDrive& drive = urban_radar_drive(1);
  const auto detections = radar_detections(drive, 5.0, sim::RadarOptions::conti_ars408(), 1);
  std::vector<io::InsRecord> every_two_seconds;
  for (std::size_t i = 0; i < drive.simulation.ins.size(); i += 200) {
    every_two_seconds.push_back(drive.simulation.ins[i]);
  }
  const CalibrationResult result = calibrate_radar(detections, every_two_seconds);
  EXPECT_FALSE(result.ok());
  EXPECT_GT(result.rejections.at("in_ins_gap"), 0);
  EXPECT_THAT(result.reason, HasSubstr("max_ins_gap_s"));
}

// Issue 11: identical result bytes (timing left out) across runs and thread counts.
TEST(RadarCalibration, IdenticalBytesAcrossRunsAndThreadCounts) {
  const RadarDrive& drive = urban_radar_drive(2);
  const auto detections = radar_detections(drive, -3.0, sim::RadarOptions::conti_ars408(), 2);
  io::ResultJsonOptions reproducible;
  reproducible.include_timing = false;
  const auto run = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return io::format_result_json(calibrate_radar(detections, drive.simulation.ins), reproducible);
  };
  const std::string first = run(2);
  EXPECT_EQ(run(2), first);
  EXPECT_EQ(run(1), first);
}

TEST(RadarCalibration, NoDetectionsIsInsufficientDataNotACrash) {
  const RadarDrive& drive = urban_radar_drive(1);
  const CalibrationResult result = calibrate_radar({}, drive.simulation.ins);
  EXPECT_FALSE(result.ok());
  EXPECT_THAT(result.reason, HasSubstr("only 0 radar detections"));
}

TEST(RadarCalibration, OptionsAreChecked) {
  RadarCalibrationOptions options;
  options.velocity.search_step = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(radar_method_from_string("velocity"), RadarMethod::kVelocity);
  EXPECT_THROW(radar_method_from_string("doppler"), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::radar
