#include "x2car/ins/ins_calibration.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::ins {
namespace {

using testing::AngleNearDeg;
using ::testing::HasSubstr;

sim::SimulationOptions drive(sim::Scenario scenario, double duration_s, std::uint64_t seed) {
  return sim::testing::simulated_drive(scenario, duration_s, seed);
}

struct Errors {
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;
};

Errors calibrate_and_compare(const sim::SimulationOptions& options,
                             const InsCalibrationOptions& calibration = {}) {
  const sim::Simulation simulation = sim::simulate(options);
  const CalibrationResult result = calibrate_ins(simulation.ins, calibration);
  EXPECT_TRUE(result.ok()) << result.reason;
  if (!result.ok()) return {NAN, NAN};
  EXPECT_FALSE(result.roll) << "roll is not observable and must be null";
  const EulerAngles truth = simulation.truth.vehicle_from_sensor.at("ins").rotation;
  return {deg_from_rad(angle_difference(*result.yaw, truth.yaw)),
          deg_from_rad(angle_difference(*result.pitch, truth.pitch))};
}

// Issue 4: urban, highway and mixed, 120 s, RTK, 5 seeds: |yaw| and |pitch| errors <= 0.05 deg.
// Measured: yaw within 0.03 deg, pitch within 0.03 deg.
TEST(InsCalibration, RtkDrivesMeetFiveHundredthsOfADegree) {
  for (const auto scenario :
       {sim::Scenario::kUrban, sim::Scenario::kHighway, sim::Scenario::kMixed}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      SCOPED_TRACE(::testing::Message() << sim::to_string(scenario) << " seed " << seed);
      const Errors errors = calibrate_and_compare(drive(scenario, 120.0, seed));
      EXPECT_LE(std::abs(errors.yaw_deg), 0.05);
      EXPECT_LE(std::abs(errors.pitch_deg), 0.05);
    }
  }
}

// The paper's track-heading yaw alone meets the same bound with RTK positions.
TEST(InsCalibration, TrackHeadingMethodAloneWithRtk) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    InsCalibrationOptions options;
    options.yaw_method = YawMethod::kTrackHeading;
    EXPECT_LE(
        std::abs(calibrate_and_compare(drive(sim::Scenario::kUrban, 120.0, seed), options).yaw_deg),
        0.05);
  }
}

// Issue 4: SPS (~1 m position noise): |yaw error| <= 0.3 deg. Measured: within 0.035 deg, because
// the automatic choice takes the velocity method's yaw (the track's heading alone is off by up to
// 0.7 deg on these drives).
TEST(InsCalibration, SpsPositionsStillGiveTheYaw) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    sim::SimulationOptions options = drive(sim::Scenario::kUrban, 120.0, seed);
    options.ins = sim::InsOptions::sps();
    EXPECT_LE(std::abs(calibrate_and_compare(options).yaw_deg), 0.3);
  }
}

TEST(InsCalibration, SignCheckADeviceYawedTwoDegreesLeftReportsPlusTwo) {
  sim::SimulationOptions options = drive(sim::Scenario::kStraight, 60.0, 4);
  io::SensorMounting mounting;
  mounting.translation = {1.0, 0.0, 1.0};
  mounting.rotation = {0.0, 0.0, rad_from_deg(2.0)};
  options.mountings["ins"] = mounting;
  const sim::Simulation simulation = sim::simulate(options);
  const CalibrationResult result = calibrate_ins(simulation.ins);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_THAT(*result.yaw, AngleNearDeg(rad_from_deg(2.0), 0.05));
  EXPECT_THAT(*result.pitch, AngleNearDeg(0.0, 0.05));
}

TEST(InsCalibration, StandstillStopsAndReversingAreRejectedAndCounted) {
  sim::SimulationOptions options = drive(sim::Scenario::kUrban, 120.0, 2);
  options.motion.start_standstill_s = 8.0;
  options.motion.reverse_m = 6.0;
  options.motion.reverse_at_start = true;
  const sim::Simulation simulation = sim::simulate(options);
  const CalibrationResult result = calibrate_ins(simulation.ins);
  ASSERT_TRUE(result.ok()) << result.reason;
  // 8 s standing at 100 Hz, plus the stops of the urban drive.
  EXPECT_GE(result.rejections.at("slow"), 800);
  // Reversing 6 m at up to 1.5 m/s: mostly slower than 3 m/s, and recognised as reversing where
  // faster than 0.5 m/s.
  EXPECT_GT(result.rejections.at("reversing"), 200);
  const EulerAngles truth = simulation.truth.vehicle_from_sensor.at("ins").rotation;
  EXPECT_THAT(*result.yaw, AngleNearDeg(truth.yaw, 0.05));
  EXPECT_THAT(*result.pitch, AngleNearDeg(truth.pitch, 0.05));
}

// 10 s on a 30 m circle at 8 m/s, 100 Hz, with a device yawed 1 deg: never straight.
std::vector<io::InsRecord> circle_drive() {
  std::vector<io::InsRecord> records;
  const double radius = 30.0, speed = 8.0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = i * 0.01;
    const double angle = speed * t / radius;
    io::InsRecord record;
    record.time = t;
    record.position_enu = {radius * std::sin(angle), radius * (1.0 - std::cos(angle)), 0.0};
    record.velocity_enu = {speed * std::cos(angle), speed * std::sin(angle), 0.0};
    record.attitude = {0.0, 0.0, wrap_angle(angle + rad_from_deg(1.0))};
    records.push_back(record);
  }
  return records;
}

TEST(InsCalibration, TurningOnlyIsInsufficientDataAndSaysWhatIsMissing) {
  const CalibrationResult result = calibrate_ins(circle_drive());
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_FALSE(result.yaw);
  EXPECT_FALSE(result.pitch);
  EXPECT_THAT(result.reason, HasSubstr("only 0.0 s of usable driving"));
  EXPECT_THAT(result.reason, HasSubstr("need 20 s"));
  EXPECT_THAT(result.reason, HasSubstr("1001 in turns"));
  EXPECT_EQ(result.rejections.at("curved"), 1001);
}

TEST(InsCalibration, AFewSamplesAreInsufficientDataNotACrash) {
  std::vector<io::InsRecord> records = circle_drive();
  records.resize(5);
  const CalibrationResult result = calibrate_ins(records);
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_THAT(result.reason, HasSubstr("only 5 GNSS/INS samples"));
  EXPECT_EQ(calibrate_ins({}).status, CalibrationStatus::kInsufficientData);
}

TEST(InsCalibration, KeepsTheSeriesAndDiagnosticsForTheReport) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kUrban, 60.0, 1));
  const CalibrationResult result = calibrate_ins(simulation.ins);
  ASSERT_TRUE(result.ok());
  std::vector<std::string> names;
  for (const Series& series : result.series) names.push_back(series.name);
  EXPECT_THAT(names, ::testing::IsSupersetOf({"track_heading", "sensor_heading", "heading_offset",
                                              "segment_yaw", "segment_pitch"}));
  EXPECT_EQ(result.series.front().time.size(), simulation.ins.size());
  for (const Series& series : result.series) {  // every series has its times, segments included
    EXPECT_EQ(series.time.size(), series.value.size()) << series.name;
  }
  EXPECT_TRUE(result.diagnostics.contains("velocity_method_yaw_deg"));
  EXPECT_TRUE(result.diagnostics.contains("track_method_yaw_deg"));
  EXPECT_GE(result.support.at("segments"), 1);
  InsCalibrationOptions without_series;
  without_series.keep_series = false;
  EXPECT_TRUE(calibrate_ins(simulation.ins, without_series).series.empty());
}

// Issue 11: a one-week forward jump in the time stamps of a 12 k-row log cost 12 s and 490 MB
// (the spline spanned the gap). Split at the gap, each piece is smoothed alone: the result is that
// of the log without the jump, less what the extra run ends trim.
TEST(InsCalibration, AMillionSecondJumpInTheStampsCalibratesAsWithoutIt) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kUrban, 120.0, 1));
  std::vector<io::InsRecord> jumped = simulation.ins;
  for (std::size_t i = jumped.size() / 2; i < jumped.size(); ++i) jumped[i].time += 1e6;
  const CalibrationResult plain = calibrate_ins(simulation.ins);
  const CalibrationResult result = calibrate_ins(jumped);
  ASSERT_TRUE(plain.ok()) << plain.reason;
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.support.at("pieces"), 2);
  EXPECT_EQ(result.rejections.at("short_piece"), 0);
  EXPECT_THAT(*result.yaw, AngleNearDeg(*plain.yaw, 0.01));
  EXPECT_THAT(*result.pitch, AngleNearDeg(*plain.pitch, 0.01));
  const EulerAngles truth = simulation.truth.vehicle_from_sensor.at("ins").rotation;
  EXPECT_THAT(*result.yaw, AngleNearDeg(truth.yaw, 0.05));
}

// Valid but odd logs end in insufficient data with the counts, never in an internal error.
TEST(InsCalibration, OddLogsAreInsufficientDataNotInternalErrors) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kHighway, 60.0, 4));
  // 3 s bursts 10 s apart: every piece too short to hold a 5 s run.
  std::vector<io::InsRecord> bursts;
  for (const io::InsRecord& record : simulation.ins) {
    if (std::fmod(record.time, 10.0) < 3.0) bursts.push_back(record);
  }
  const CalibrationResult result = calibrate_ins(bursts);
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(result.rejections.at("short_piece"), static_cast<std::int64_t>(bursts.size()));
  EXPECT_THAT(result.reason, HasSubstr("too short to smooth"));
  // A second of 1 kHz stamps, and a log whose positions never change.
  std::vector<io::InsRecord> dense(simulation.ins.begin(), simulation.ins.begin() + 1000);
  for (std::size_t i = 0; i < dense.size(); ++i) dense[i].time = 1e-3 * static_cast<double>(i);
  EXPECT_EQ(calibrate_ins(dense).status, CalibrationStatus::kInsufficientData);
  std::vector<io::InsRecord> parked = simulation.ins;
  for (io::InsRecord& record : parked) {
    record.position_enu = simulation.ins.front().position_enu;
    record.velocity_enu.setZero();
  }
  EXPECT_EQ(calibrate_ins(parked).status, CalibrationStatus::kInsufficientData);
}

TEST(InsCalibration, MinimumDurationCanBeRelaxedKnowingly) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kHighway, 20.0, 2));
  const CalibrationResult strict = calibrate_ins(simulation.ins);
  ASSERT_FALSE(strict.ok());
  EXPECT_THAT(strict.reason, HasSubstr("need 20 s"));
  InsCalibrationOptions relaxed;
  relaxed.alignment.min_valid_duration_s = 5.0;
  const CalibrationResult result = calibrate_ins(simulation.ins, relaxed);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_LT(result.diagnostics.at("valid_duration_s"), 20.0);
}

// Issue 12: a city drive (short blocks, a turn at most corners) cut into minutes, as the paper's
// protocol does. With the turns used every minute gives the yaw within 0.1 deg (measured: within
// 0.02 deg); the paper's straight-only gates leave some minutes without one (`make bench`,
// BM_InsYawPerMinute: 60 % of the minutes with them, 100 % with the turns, seeds 1-3).
TEST(InsCalibration, EveryMinuteOfCityDrivingGivesTheYawWithTheTurnsUsed) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kCity, 180.0, 1));
  const double truth = simulation.truth.vehicle_from_sensor.at("ins").rotation.yaw;
  InsCalibrationOptions paper;
  paper.alignment.turns.samples = TurnSamples::kExclude;
  int paper_minutes = 0;
  for (double begin = 0.0; begin < 180.0; begin += 60.0) {
    SCOPED_TRACE(::testing::Message() << "minute from " << begin << " s");
    std::vector<io::InsRecord> minute;
    for (const io::InsRecord& record : simulation.ins) {
      if (record.time >= begin && record.time < begin + 60.0) minute.push_back(record);
    }
    const CalibrationResult result = calibrate_ins(minute);
    ASSERT_TRUE(result.ok()) << result.reason;
    EXPECT_EQ(result.diagnostics.at("turns_used"), 1.0);
    EXPECT_THAT(*result.yaw, AngleNearDeg(truth, 0.1));
    if (calibrate_ins(minute, paper).ok()) ++paper_minutes;
  }
  EXPECT_LT(paper_minutes, 3);
}

// Issue 11: identical result bytes (timing left out) across runs and thread counts.
TEST(InsCalibration, IdenticalBytesAcrossRunsAndThreadCounts) {
  const sim::Simulation simulation = sim::simulate(drive(sim::Scenario::kMixed, 60.0, 3));
  io::ResultJsonOptions reproducible;
  reproducible.include_timing = false;
  const auto run = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return io::format_result_json(calibrate_ins(simulation.ins), reproducible);
  };
  const std::string first = run(2);
  EXPECT_EQ(run(2), first);
  EXPECT_EQ(run(1), first);
}

}  // namespace
}  // namespace x2car::ins
