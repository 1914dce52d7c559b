#include "x2car/radar/radar_position_method.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

namespace testing = sim::testing;

using testing::ConstructedTarget;
using ::testing::HasSubstr;
using testing::kRadarLeverArm;

RadarCalibrationOptions options_for(RadarMethod method) {
  RadarCalibrationOptions options;
  options.method = method;
  options.lever_arm_in_vehicle = kRadarLeverArm.head<2>();
  return options;
}

double yaw_error_deg(const CalibrationResult& result, double truth_deg) {
  EXPECT_TRUE(result.ok()) << result.reason;
  if (!result.ok()) return NAN;
  EXPECT_TRUE(result.yaw_std && std::isfinite(*result.yaw_std) && *result.yaw_std > 0.0);
  EXPECT_FALSE(result.roll);
  EXPECT_FALSE(result.pitch);
  return deg_from_rad(angle_difference(*result.yaw, rad_from_deg(truth_deg)));
}

// Issue 6: position method |error| <= 0.2 deg on urban 60 s, truth 0, 10, 20, -7 deg. The full 5
// seeds x 2 layouts run in bench/radar_bench.cpp (measured worst: Conti 0.046 deg, Delphi 0.050
// deg); here seeds 1-2.
void expect_position_accuracy(const sim::RadarOptions& radar) {
  for (const double truth_deg : {0.0, 10.0, 20.0, -7.0}) {
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      SCOPED_TRACE(::testing::Message() << "truth " << truth_deg << " deg, seed " << seed);
      const testing::RadarDrive& drive = testing::urban_radar_drive(seed);
      const auto detections = testing::radar_detections(drive, truth_deg, radar, seed);
      const CalibrationResult result =
          calibrate_radar(detections, drive.simulation.ins, options_for(RadarMethod::kPosition));
      EXPECT_EQ(result.method, "position");
      EXPECT_LE(std::abs(yaw_error_deg(result, truth_deg)), 0.2);
      if (result.ok()) {
        EXPECT_GE(result.support.at("static_objects"), 20);
      }
    }
  }
}

TEST(RadarPositionMethod, ContiMeetsTwoTenthsOfADegree) {
  expect_position_accuracy(sim::RadarOptions::conti_ars408());
}

TEST(RadarPositionMethod, DelphiMeetsTwoTenthsOfADegree) {
  expect_position_accuracy(sim::RadarOptions::delphi_esr());
}

// Without the lever arm only pairs over which the car barely turned are used.
TEST(RadarPositionMethod, WithoutLeverArm) {
  const testing::RadarDrive& drive = testing::urban_radar_drive(3);
  const auto detections =
      testing::radar_detections(drive, -7.0, sim::RadarOptions::conti_ars408(), 3);
  RadarCalibrationOptions options;
  options.method = RadarMethod::kPosition;
  const CalibrationResult result = calibrate_radar(detections, drive.simulation.ins, options);
  EXPECT_LE(std::abs(yaw_error_deg(result, -7.0)), 0.2);
  EXPECT_GT(result.rejections.at("turning_pairs") + result.rejections.at("turning"), 0);
}

// The radar's samples of a constructed drive, as the position method sees them.
std::vector<RadarSample> constructed_samples(const testing::ConstructedRadarDrive& drive) {
  return radar_ego_motion(drive.detections, drive.ins, kRadarLeverArm.head<2>()).samples;
}

// Triangle test: a static post closes the triangle of the two lines of sight and the baseline and
// gives the exact yaw; a car ahead driving away at 6 m/s and an oncoming car at 8 m/s do not.
TEST(RadarPositionMethod, TriangleTestSeparatesStaticFromMoving) {
  const double yaw = rad_from_deg(12.0);
  const testing::ConstructedRadarDrive drive = testing::constructed_radar_drive(
      10.0, 6.0, yaw,
      {{.position = {60.0, 6.0}, .track_id = 1},
       {.position = {30.0, 0.3}, .velocity = {6.0, 0.0}, .track_id = 2},
       {.position = {90.0, 3.5}, .velocity = {-8.0, 0.0}, .track_id = 3, .min_range = 30.0}});
  const std::vector<RadarSample> samples = constructed_samples(drive);
  const RadarPositionMethodOptions options;
  for (const int track : {1, 2, 3}) {
    std::vector<RadarSample> track_samples;
    for (const RadarSample& s : samples) {
      if (s.track_id == track) track_samples.push_back(s);
    }
    ASSERT_GE(track_samples.size(), 20u) << "track " << track;
    const PairEstimate pair =
        estimate_pair(track_samples.front(), track_samples[track_samples.size() / 2],
                      kRadarLeverArm.head<2>(), options);
    ASSERT_TRUE(pair.defined);
    EXPECT_GT(pair.baseline_m, 10.0);
    const bool closes = std::abs(pair.closure_m) <= options.triangle_sigmas * pair.closure_sigma_m;
    SCOPED_TRACE(::testing::Message() << "track " << track << " closure " << pair.closure_m);
    if (track == 1) {
      EXPECT_TRUE(closes);
      EXPECT_NEAR(pair.yaw, yaw, 1e-6);
      EXPECT_NEAR(pair.confidence, 1.0, 1e-6);
    } else {
      EXPECT_FALSE(closes);
      EXPECT_GT(std::abs(pair.closure_m), 5.0);
    }
  }
}

// Several static posts along a straight road among moving cars: the method keeps the posts only.
TEST(RadarPositionMethod, ConstructedDriveKeepsOnlyStaticObjects) {
  std::vector<ConstructedTarget> targets;
  for (int k = 0; k < 12; ++k) {
    targets.push_back({.position = {40.0 + 25.0 * k, k % 2 == 0 ? -5.0 : 8.5}, .track_id = k});
  }
  targets.push_back({.position = {20.0, 0.3}, .velocity = {10.5, 0.0}, .track_id = 40});
  targets.push_back({.position = {200.0, 3.5}, .velocity = {-9.0, 0.0}, .track_id = 41});
  const testing::ConstructedRadarDrive drive =
      testing::constructed_radar_drive(10.0, 30.0, -0.1, targets);
  RadarCalibrationOptions options = options_for(RadarMethod::kPosition);
  options.position.min_pairs = 10;
  const CalibrationResult result = calibrate_radar(drive.detections, drive.ins, options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(*result.yaw, -0.1, 1e-6);
  EXPECT_EQ(result.support.at("static_objects"), 12);
  EXPECT_EQ(result.rejections.at("moving_objects"), 2);
}

// Targets dead ahead: the triangle is flat (the paper's angle test and its arccos are 0/0 there),
// the exact form still closes it and recovers the yaw from the line of sight.
TEST(RadarPositionMethod, TargetsDeadAhead) {
  const double yaw = rad_from_deg(5.0);
  std::vector<ConstructedTarget> targets;
  for (int k = 0; k < 20; ++k) {
    // On the radar's own line (y = the lever arm's), seen from 70 m down to 20 m.
    targets.push_back({.position = {100.0 + 30.0 * k, 0.3}, .track_id = k, .min_range = 20.0});
  }
  const testing::ConstructedRadarDrive drive =
      testing::constructed_radar_drive(12.0, 60.0, yaw, targets);
  const CalibrationResult result =
      calibrate_radar(drive.detections, drive.ins, options_for(RadarMethod::kPosition));
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_NEAR(*result.yaw, yaw, 1e-6);
  EXPECT_TRUE(std::isfinite(*result.yaw_std));
}

// Each target is tracked for 0.8 s at 4 m/s: pairs span under 2 m, too thin a triangle.
TEST(RadarPositionMethod, TinyBaselinesAreInsufficientData) {
  std::vector<ConstructedTarget> targets;
  for (int k = 0; k < 40; ++k) {
    targets.push_back({.position = {20.0 + 3.0 * k, -6.0},
                       .track_id = k,
                       .visible_from = 0.9 * k,
                       .visible_to = 0.9 * k + 0.8});
  }
  const testing::ConstructedRadarDrive drive =
      testing::constructed_radar_drive(4.0, 40.0, 0.05, targets);
  const CalibrationResult result =
      calibrate_radar(drive.detections, drive.ins, options_for(RadarMethod::kPosition));
  EXPECT_FALSE(result.ok());
  EXPECT_FALSE(result.yaw);
  EXPECT_THAT(result.reason, HasSubstr("shorter baseline"));
  EXPECT_GT(result.rejections.at("short_baseline_pairs"), 0);
}

// A standing car: no baseline (0/0) and no Doppler; insufficient data with a reason, no NaN.
TEST(RadarPositionMethod, StandingCarIsInsufficientData) {
  const testing::ConstructedRadarDrive drive =
      testing::constructed_radar_drive(0.0, 20.0, 0.1, {{.position = {30.0, 5.0}, .track_id = 1}});
  for (const RadarMethod method : {RadarMethod::kPosition, RadarMethod::kAuto}) {
    const CalibrationResult result =
        calibrate_radar(drive.detections, drive.ins, options_for(method));
    EXPECT_FALSE(result.ok());
    EXPECT_FALSE(result.yaw);
    EXPECT_THAT(result.reason, HasSubstr("fastest 0.0 m/s"));
  }
  const std::vector<RadarSample> samples = constructed_samples(drive);
  ASSERT_GE(samples.size(), 2u);
  const PairEstimate pair =
      estimate_pair(samples.front(), samples.back(), kRadarLeverArm.head<2>(), {});
  EXPECT_FALSE(pair.defined);
  EXPECT_EQ(velocity_confidence(samples.front(), 0.1, {}), 0.0);
}

// A track id the radar hands to another target, after a gap or at once, starts a new object.
TEST(RadarPositionMethod, ReusedTrackIdsAreSplit) {
  const testing::ConstructedRadarDrive drive = testing::constructed_radar_drive(
      10.0, 12.0, 0.0,
      {{.position = {50.0, 5.0}, .track_id = 7, .visible_to = 3.0},
       {.position = {90.0, -6.0}, .track_id = 7, .visible_from = 3.05, .visible_to = 6.0},
       {.position = {150.0, 6.0}, .track_id = 7, .visible_from = 7.0}});
  const std::vector<RadarSample> samples = constructed_samples(drive);
  const std::vector<int> one_segment(samples.size(), 0);
  const ObjectGrouping grouping = group_objects(samples, one_segment, {});
  ASSERT_EQ(grouping.objects.size(), 3u);
  for (const RadarObject& object : grouping.objects) EXPECT_GT(object.indices.size(), 20u);
}

// ---- issue 12: any direction, clusters without track ids, wrong inputs refused ----------------

// The drive seen by a Conti-like radar facing `yaw_deg`, with or without track ids, calibrated by
// the position method with the radar's lever arm.
CalibrationResult position_result_facing(
    double yaw_deg, bool track_ids, std::uint64_t seed,
    const std::function<void(io::RadarDetection&)>& spoil = [](io::RadarDetection&) {}) {
  const testing::RadarDrive& drive = testing::urban_radar_drive(seed);
  sim::RadarOptions radar = sim::RadarOptions::conti_ars408();
  radar.track_ids = track_ids;
  std::vector<io::RadarDetection> detections =
      testing::radar_detections_facing(drive, yaw_deg, radar, seed);
  for (io::RadarDetection& detection : detections) spoil(detection);
  RadarCalibrationOptions options = options_for(RadarMethod::kPosition);
  options.lever_arm_in_vehicle = testing::radar_lever_arm_for_yaw(yaw_deg).head<2>();
  return calibrate_radar(detections, drive.simulation.ins, options);
}

// One cheap case per direction of issue 12 (seed 1, clusters without track ids; the full grid of
// 5 seeds, Conti and Delphi, with and without ids is BM_RadarPositionEveryDirection in
// bench/radar_bench.cpp). Front, rear and diagonal radars see many static objects: |error| <=
// 0.1 deg. Side radars see few (posts pass abeam in a second or two) and their pairs are limited by
// the range noise: |error| <= 0.4 deg, within 3 reported standard errors (measured on seed 1:
// 0.11 deg at +90, 0.34 deg at -90 with a standard error of 0.12 deg).
TEST(RadarPositionMethod, EveryDirectionWithoutTrackIds) {
  for (const double yaw_deg : {0.0, 25.0, -25.0, 85.0, -85.0, 90.0, -90.0, 180.0}) {
    SCOPED_TRACE(::testing::Message() << "yaw " << yaw_deg << " deg");
    const CalibrationResult result = position_result_facing(yaw_deg, false, 1);
    const double error_deg = yaw_error_deg(result, yaw_deg);
    if (!result.ok()) continue;
    EXPECT_EQ(result.diagnostics.at("associated"), 1.0);
    EXPECT_GT(result.support.at("associated_tracks"), 100);
    const bool sideways = std::abs(std::abs(yaw_deg) - 90.0) <= 10.0;
    EXPECT_LE(std::abs(error_deg), sideways ? 0.4 : 0.1);
    EXPECT_LE(std::abs(error_deg), 3.0 * deg_from_rad(*result.yaw_std));
  }
}

// With the radar's ids the association is not used (unless always_associate).
TEST(RadarPositionMethod, TrackIdsAreUsedWhenThereAreAny) {
  const CalibrationResult result = position_result_facing(180.0, true, 2);
  EXPECT_LE(std::abs(yaw_error_deg(result, 180.0)), 0.1);
  EXPECT_EQ(result.diagnostics.at("associated"), 0.0);
  EXPECT_FALSE(result.support.contains("associated_tracks"));
}

// Azimuths in degrees read as radians, radians read as degrees, a flipped range-rate sign: never
// ok, and the reason names what is wrong (issue 12, item 2).
TEST(RadarPositionMethod, WrongUnitsAndAFlippedRangeRateAreNotOk) {
  for (const bool track_ids : {true, false}) {
    for (const double yaw_deg : {0.0, 90.0}) {
      SCOPED_TRACE(::testing::Message() << "yaw " << yaw_deg << " deg, ids " << track_ids);
      const CalibrationResult degrees = position_result_facing(
          yaw_deg, track_ids, 3,
          [](io::RadarDetection& d) { d.azimuth = deg_from_rad(d.azimuth); });
      EXPECT_EQ(degrees.status, CalibrationStatus::kUnreliable);
      EXPECT_THAT(degrees.reason, HasSubstr("not in radians"));
      EXPECT_FALSE(degrees.yaw);
      const CalibrationResult radians = position_result_facing(
          yaw_deg, track_ids, 3,
          [](io::RadarDetection& d) { d.azimuth = rad_from_deg(d.azimuth); });
      EXPECT_EQ(radians.status, CalibrationStatus::kUnreliable);
      EXPECT_THAT(radians.reason, HasSubstr("radians read as degrees"));
      const CalibrationResult flipped = position_result_facing(
          yaw_deg, track_ids, 3, [](io::RadarDetection& d) { d.range_rate = -d.range_rate; });
      EXPECT_FALSE(flipped.ok()) << flipped.reason;
      EXPECT_THAT(flipped.reason, HasSubstr("range rate"));
    }
  }
}

// The GNSS/INS speed 4 % too fast (a CAN speed's scale error): the static objects' apparent
// displacements give the scale, the baselines are corrected and the yaw is as without the error;
// a speed 25 % off (other units, a broken sensor) is not ok (15 % off: unreliable, the scale
// check). Measured over seeds 1-5 and
// directions 10, 90, 180 deg with and without ids: the scale within 0.3 % of the truth for 1.00,
// 1.02 and 1.05, the yaw errors as without it.
TEST(RadarPositionMethod, SpeedScaleIsEstimatedAndCorrected) {
  const testing::RadarDrive& drive = testing::urban_radar_drive(2);
  const auto detections =
      testing::radar_detections(drive, 10.0, sim::RadarOptions::conti_ars408(), 2);
  const RadarCalibrationOptions options = options_for(RadarMethod::kPosition);
  const CalibrationResult plain = calibrate_radar(detections, drive.simulation.ins, options);
  for (const double scale : {1.04, 1.25}) {
    SCOPED_TRACE(::testing::Message() << "speed scale " << scale);
    std::vector<io::InsRecord> ins = drive.simulation.ins;
    for (io::InsRecord& record : ins) record.velocity_enu *= scale;
    const CalibrationResult result = calibrate_radar(detections, ins, options);
    if (scale < 1.1) {
      EXPECT_LE(std::abs(yaw_error_deg(result, 10.0)), 0.1);
      EXPECT_NEAR(deg_from_rad(*result.yaw), deg_from_rad(*plain.yaw), 0.02);
      EXPECT_NEAR(result.diagnostics.at("speed_scale"), scale, 0.005);
      EXPECT_NEAR(plain.diagnostics.at("speed_scale"), 1.0, 0.005);
    } else {
      EXPECT_FALSE(result.ok()) << result.reason;  // the triangles do not close: too few objects
      EXPECT_FALSE(result.yaw);
    }
  }
}

TEST(RadarPositionMethod, OptionsAreChecked) {
  RadarCalibrationOptions options;
  options.position.min_baseline_m = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.automatic.agreement_sigmas = -1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.position.min_confidence = 0.0;  // pairs of weight 0 would leave no weighted mean
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.position.association_gate_sigmas = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.position.min_static_object_fraction = 1.5;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(radar_method_from_string("position"), RadarMethod::kPosition);
}

}  // namespace
}  // namespace x2car::radar
