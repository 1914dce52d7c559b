#include "x2car/core/track_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car {
namespace {

using testing::AngleNearDeg;

// A level car (no grade, no roll) driven at 100 Hz with heading(t) and signed speed(t), the
// sensor at the rear axle (no lever arm) with mounting `vehicle_from_sensor`. Positions are
// integrated with the midpoint rule on a 1 ms grid.
SensorTrack drive(double duration_s, const std::function<double(double)>& heading,
                  const std::function<double(double)>& speed, const EulerAngles& mounting,
                  bool with_velocity) {
  SensorTrack track;
  const Eigen::Matrix3d vehicle_from_sensor = rotation_from_euler(mounting);
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  const double dt = 0.001;
  for (int step = 0; step <= static_cast<int>(std::lround(duration_s / dt)); ++step) {
    const double t = step * dt;
    const auto velocity_at = [&](double time) -> Eigen::Vector3d {
      return Eigen::Vector3d(std::cos(heading(time)), std::sin(heading(time)), 0.0) * speed(time);
    };
    if (step % 10 == 0) {
      track.time.push_back(t);
      track.position_enu.push_back(position);
      track.world_from_sensor.push_back(rotation_from_euler({0.0, 0.0, heading(t)}) *
                                        vehicle_from_sensor);
      if (with_velocity) track.velocity_enu.push_back(velocity_at(t));
    }
    position += velocity_at(t + dt / 2) * dt;
  }
  return track;
}

const EulerAngles kMounting{rad_from_deg(2.5), rad_from_deg(-1.5), rad_from_deg(2.0)};

TEST(TrackAlignment, RecoversYawAndPitchOfALevelCarOnAWindingRoad) {
  // Heading sways +-0.2 rad over a minute at 12 m/s: |curvature| <= 0.0017 1/m, all valid.
  const auto heading = [](double t) { return 0.3 + 0.2 * std::sin(2 * kPi * t / 60.0); };
  const auto speed = [](double) { return 12.0; };
  for (const bool with_velocity : {true, false}) {
    SCOPED_TRACE(with_velocity ? "sensor velocity" : "spline velocity");
    const TrackAlignment alignment =
        align_track(drive(120.0, heading, speed, kMounting, with_velocity));
    ASSERT_FALSE(alignment.insufficient_reason) << *alignment.insufficient_reason;
    EXPECT_EQ(alignment.velocity_from_sensor, with_velocity);
    // Exact data: only the spline's smoothing error remains.
    EXPECT_THAT(alignment.yaw->value, AngleNearDeg(kMounting.yaw, 0.002));
    EXPECT_THAT(alignment.velocity_yaw_estimate->value, AngleNearDeg(kMounting.yaw, 0.002));
    EXPECT_THAT(alignment.velocity_pitch_estimate->value, AngleNearDeg(kMounting.pitch, 0.002));
    // So gentle a road cannot separate a lever arm from the yaw (the curvature hardly varies): the
    // paper's gates are used, which trim 1 s at both ends.
    EXPECT_FALSE(alignment.turns_used);
    EXPECT_TRUE(alignment.lever_arm_rejected);
    EXPECT_NEAR(alignment.valid_duration_s, 120.0 - 2 * 1.0, 0.05);
  }
}

TEST(TrackAlignment, SignCheckASensorYawedLeftReportsPositiveYaw) {
  const auto heading = [](double) { return -2.0; };
  const auto speed = [](double) { return 8.0; };
  const TrackAlignment alignment =
      align_track(drive(40.0, heading, speed, {0.0, 0.0, rad_from_deg(2.0)}, true));
  ASSERT_TRUE(alignment.yaw);
  EXPECT_THAT(alignment.yaw->value, AngleNearDeg(rad_from_deg(2.0), 1e-4));
  EXPECT_THAT(alignment.velocity_yaw_estimate->value, AngleNearDeg(rad_from_deg(2.0), 1e-4));
  // A sensor pitched down by 3 deg (positive pitch, DESIGN §1) reports +3 deg.
  const TrackAlignment pitched =
      align_track(drive(40.0, heading, speed, {0.0, rad_from_deg(3.0), 0.0}, true));
  EXPECT_THAT(pitched.velocity_pitch_estimate->value, AngleNearDeg(rad_from_deg(3.0), 1e-4));
}

// The velocity's elevation over the sensor's xy plane: the pitch of a sensor facing ahead, the
// roll of one facing sideways, asin(cos yaw sin pitch cos roll + sin yaw sin roll) at any yaw
// (the first row of vehicle_from_sensor's transpose's z); the velocity pitch stays the pitch.
TEST(TrackAlignment, TheVelocitysElevationOverTheSensorsPlaneMixesRollAndPitchByTheYaw) {
  const auto heading = [](double t) { return 0.3 + 0.2 * std::sin(2 * kPi * t / 60.0); };
  const auto speed = [](double) { return 12.0; };
  const double roll = rad_from_deg(2.5), pitch = rad_from_deg(-1.5);
  for (const double yaw_deg : {0.0, 90.0, 180.0, -135.0}) {
    SCOPED_TRACE(yaw_deg);
    const double yaw = rad_from_deg(yaw_deg);
    const TrackAlignment alignment =
        align_track(drive(60.0, heading, speed, {roll, pitch, yaw}, true));
    ASSERT_TRUE(alignment.velocity_elevation_estimate);
    const double expected = std::asin(std::cos(yaw) * std::sin(pitch) * std::cos(roll) +
                                      std::sin(yaw) * std::sin(roll));
    EXPECT_THAT(alignment.velocity_elevation_estimate->value, AngleNearDeg(expected, 0.002));
    EXPECT_THAT(alignment.velocity_pitch_estimate->value, AngleNearDeg(pitch, 0.002));
  }
}

TEST(TrackAlignment, ReversingSamplesAreExcludedAndCounted) {
  // 5 m/s, slowing to -1.5 m/s at 30-33 s, reversing until 40 s, then forward again from 43 s.
  const auto speed = [](double t) {
    if (t < 30.0) return 5.0;
    if (t < 33.0) return 5.0 - 6.5 * (t - 30.0) / 3.0;
    if (t < 40.0) return -1.5;
    if (t < 43.0) return -1.5 + 6.5 * (t - 40.0) / 3.0;
    return 5.0;
  };
  const auto heading = [](double) { return 1.0; };
  TrackAlignmentOptions options;
  options.segments.min_speed = 1.0;  // let the slow reversing reach the reversing test
  const TrackAlignment alignment =
      align_track(drive(80.0, heading, speed, kMounting, true), options);
  ASSERT_TRUE(alignment.yaw);
  std::int64_t reversing = 0;
  for (const auto flag : alignment.reversing) reversing += flag;
  // Faster than 0.5 m/s backwards from ~32.5 s to ~40.5 s.
  EXPECT_NEAR(static_cast<double>(reversing), 800.0, 60.0);
  EXPECT_EQ(alignment.segmentation.rejections.excluded, reversing);
  EXPECT_EQ(alignment.reversing_samples, reversing);
  EXPECT_THAT(alignment.yaw->value, AngleNearDeg(kMounting.yaw, 0.002));
}

TEST(TrackAlignment, TurningOnlyIsInsufficientDataWithAReason) {
  // A 30 m circle at 8 m/s: curvature 0.033 1/m everywhere.
  const auto heading = [](double t) { return 8.0 * t / 30.0; };
  const auto speed = [](double) { return 8.0; };
  const TrackAlignment alignment = align_track(drive(10.0, heading, speed, kMounting, true));
  ASSERT_TRUE(alignment.insufficient_reason);
  EXPECT_FALSE(alignment.yaw);
  EXPECT_NE(alignment.insufficient_reason->find("only 0.0 s of usable driving"), std::string::npos)
      << *alignment.insufficient_reason;
  EXPECT_NE(alignment.insufficient_reason->find("need 20 s"), std::string::npos);
  EXPECT_NE(alignment.insufficient_reason->find("in turns"), std::string::npos);
}

// The track with every time from `from_s` on moved `by_s` later.
SensorTrack with_time_jump(SensorTrack track, double from_s, double by_s) {
  for (double& t : track.time) {
    if (t >= from_s) t += by_s;
  }
  return track;
}

TEST(TrackAlignment, ATimeGapSplitsTheTrackAndEachPieceIsSmoothedAlone) {
  const auto heading = [](double t) { return 0.3 + 0.2 * std::sin(2 * kPi * t / 60.0); };
  const auto speed = [](double) { return 12.0; };
  const SensorTrack track = drive(120.0, heading, speed, kMounting, false);
  // A week-long jump in the stamps, and Unix times after relative ones: a spline across the gap
  // would need 2e6 (or 3.4e9) knot intervals. Each piece alone needs 120.
  for (const double jump_s : {1e6, 1.7e9}) {
    SCOPED_TRACE(jump_s);
    TrackAlignmentOptions paper;  // whose runs are trimmed at their ends
    paper.turns.samples = TurnSamples::kExclude;
    const TrackAlignment alignment = align_track(with_time_jump(track, 60.0, jump_s), paper);
    ASSERT_FALSE(alignment.insufficient_reason) << *alignment.insufficient_reason;
    EXPECT_EQ(alignment.pieces, 2);
    EXPECT_EQ(alignment.short_pieces, 0);
    EXPECT_THAT(alignment.yaw->value, AngleNearDeg(kMounting.yaw, 0.002));
    EXPECT_THAT(alignment.velocity_yaw_estimate->value, AngleNearDeg(kMounting.yaw, 0.002));
    EXPECT_THAT(alignment.velocity_pitch_estimate->value, AngleNearDeg(kMounting.pitch, 0.002));
    // As without the gap, less the 1 s trimmed at each end of the two runs the gap makes.
    EXPECT_NEAR(alignment.valid_duration_s, 120.0 - 4 * 1.0, 0.1);
    EXPECT_EQ(alignment.track.time.size(), track.time.size());
  }
}

TEST(TrackAlignment, PiecesTooShortToSmoothAreLeftOutAndCounted) {
  const auto heading = [](double) { return 0.5; };
  const auto speed = [](double) { return 10.0; };
  // 0-40 s, then 3 s alone (shorter than a 5 s run), then 40 s more.
  SensorTrack track = drive(83.0, heading, speed, kMounting, true);
  track = with_time_jump(with_time_jump(track, 40.005, 100.0), 143.005, 100.0);
  const TrackAlignment alignment = align_track(track);
  ASSERT_FALSE(alignment.insufficient_reason) << *alignment.insufficient_reason;
  EXPECT_EQ(alignment.pieces, 2);
  EXPECT_EQ(alignment.short_pieces, 1);
  EXPECT_EQ(alignment.in_short_pieces, 300);  // 100 Hz for 3 s
  EXPECT_EQ(alignment.segmentation.rejections.excluded, alignment.in_short_pieces);
  EXPECT_THAT(alignment.yaw->value, AngleNearDeg(kMounting.yaw, 0.002));
}

TEST(TrackAlignment, TooFewSamplesIsInsufficientDataNotAnError) {
  const SensorTrack full = drive(
      10.0, [](double) { return 0.0; }, [](double) { return 5.0; }, kMounting, true);
  for (const std::size_t count : {0, 1, 3}) {
    SensorTrack track;
    for (std::size_t i = 0; i < count; ++i) {
      track.time.push_back(full.time[i]);
      track.position_enu.push_back(full.position_enu[i]);
      track.world_from_sensor.push_back(full.world_from_sensor[i]);
    }
    const TrackAlignment alignment = align_track(track);
    ASSERT_TRUE(alignment.insufficient_reason) << count;
    EXPECT_EQ(alignment.in_short_pieces, static_cast<std::int64_t>(count));
    EXPECT_NE(alignment.insufficient_reason->find("too short to smooth"), std::string::npos)
        << *alignment.insufficient_reason;
  }
}

TEST(TrackAlignment, RejectsMalformedTracks) {
  SensorTrack track = drive(
      10.0, [](double) { return 0.0; }, [](double) { return 5.0; }, kMounting, true);
  SensorTrack short_velocity = track;
  short_velocity.velocity_enu.pop_back();
  EXPECT_THROW(align_track(short_velocity), std::invalid_argument);
  SensorTrack repeated = track;
  repeated.time[5] = repeated.time[4];
  EXPECT_THROW(align_track(repeated), std::invalid_argument);
}

}  // namespace
}  // namespace x2car

namespace x2car {
namespace {

// A level car at a constant 6 m/s: 4 s straight, a 90-degree left turn at a constant yaw rate
// on a 25 m radius (1.44 m/s^2), 4 s straight, the same turn to the right, and so on for 63 s,
// sampled at 100 Hz. The sensor sits at `lever_arm` [m] in the vehicle frame (x ahead of the rear
// axle), so its track and velocity in the turns are the rear axle's turned by asin(r_x / 25 m).
// `all_left`: every turn to the left (a drive round the block).
SensorTrack city_blocks(const EulerAngles& mounting, const Eigen::Vector3d& lever_arm,
                        bool all_left = false) {
  constexpr double kSpeed = 6.0, kRadius = 25.0, kStraight = 4.0;
  const double turn_s = kPi / 2.0 * kRadius / kSpeed;
  const double cycle = 2.0 * (kStraight + turn_s);
  const auto yaw_rate = [&](double t) {
    const double phase = std::fmod(t, cycle);
    if (phase < kStraight) return 0.0;
    if (phase < kStraight + turn_s) return kSpeed / kRadius;
    if (phase < 2.0 * kStraight + turn_s) return 0.0;
    return (all_left ? 1.0 : -1.0) * kSpeed / kRadius;
  };
  const Eigen::Matrix3d vehicle_from_sensor = rotation_from_euler(mounting);
  SensorTrack track;
  Eigen::Vector3d rear_axle = Eigen::Vector3d::Zero();
  double heading = 0.4;
  const double dt = 0.001;
  for (int step = 0; step <= 63000; ++step) {
    const double t = step * dt;
    if (step % 10 == 0) {
      const Eigen::Matrix3d world_from_vehicle = rotation_from_euler({0.0, 0.0, heading});
      const Eigen::Vector3d omega(0.0, 0.0, yaw_rate(t));
      track.time.push_back(t);
      track.position_enu.push_back(rear_axle + world_from_vehicle * lever_arm);
      track.world_from_sensor.push_back(world_from_vehicle * vehicle_from_sensor);
      track.velocity_enu.push_back(world_from_vehicle *
                                   (Eigen::Vector3d(kSpeed, 0.0, 0.0) + omega.cross(lever_arm)));
    }
    const double mid_heading = heading + 0.5 * dt * yaw_rate(t);
    rear_axle += kSpeed * dt * Eigen::Vector3d(std::cos(mid_heading), std::sin(mid_heading), 0.0);
    heading += dt * yaw_rate(t + 0.5 * dt);
  }
  return track;
}

const Eigen::Vector3d kLeverArm{1.5, 0.3, 1.2};

// Issue 12: with straights of 4 s between turns, the paper's gates (|curvature| <= 0.01 1/m, runs
// of 5 s after 1 s is trimmed at each end) find no usable driving; using the turns with the fitted
// lever arm recovers the yaw within 0.1 deg (measured: within 0.01 deg) and the lever arm.
TEST(TrackAlignment, TurnsWithALeverArmGiveTheYawTheStraightsAlonePassUp) {
  const SensorTrack track = city_blocks(kMounting, kLeverArm);
  TrackAlignmentOptions paper;
  paper.turns.samples = TurnSamples::kExclude;
  const TrackAlignment straights_only = align_track(track, paper);
  ASSERT_TRUE(straights_only.insufficient_reason);
  EXPECT_NE(straights_only.insufficient_reason->find("only 0.0 s"), std::string::npos)
      << *straights_only.insufficient_reason;

  const TrackAlignment turns = align_track(track);
  ASSERT_FALSE(turns.insufficient_reason) << *turns.insufficient_reason;
  EXPECT_TRUE(turns.turns_used);
  EXPECT_GT(turns.valid_duration_s, 60.0);
  ASSERT_TRUE(turns.lever_arm_fit);
  EXPECT_NEAR(turns.lever_arm_x, kLeverArm.x(), 0.05);
  EXPECT_THAT(turns.yaw->value, AngleNearDeg(kMounting.yaw, 0.1));
  EXPECT_THAT(turns.velocity_yaw_estimate->value, AngleNearDeg(kMounting.yaw, 0.1));
  EXPECT_THAT(turns.velocity_pitch_estimate->value, AngleNearDeg(kMounting.pitch, 0.1));
  // The uncorrected turns are off by asin(1.5 / 25) = 3.4 deg: without the lever arm the yaws of
  // the left and right turns would spread the segments by degrees.
  EXPECT_LT(turns.yaw->standard_error, rad_from_deg(0.05));

  // A given lever arm is used as it is.
  TrackAlignmentOptions given;
  given.turns.lever_arm = kLeverArm;
  const TrackAlignment known = align_track(track, given);
  ASSERT_TRUE(known.yaw);
  EXPECT_FALSE(known.lever_arm_fit);
  EXPECT_EQ(known.lever_arm_x, kLeverArm.x());
  EXPECT_THAT(known.yaw->value, AngleNearDeg(kMounting.yaw, 0.1));
  EXPECT_THAT(known.velocity_yaw_estimate->value, AngleNearDeg(kMounting.yaw, 0.1));
}

// Round the block (every turn to the left): the straights between the turns still tell the yaw
// from the lever arm, so both are found.
TEST(TrackAlignment, TurnsAllOneWayStillIdentifyTheLeverArmFromTheStraights) {
  const TrackAlignment alignment = align_track(city_blocks(kMounting, kLeverArm, true));
  ASSERT_FALSE(alignment.insufficient_reason) << *alignment.insufficient_reason;
  EXPECT_TRUE(alignment.turns_used);
  EXPECT_NEAR(alignment.lever_arm_x, kLeverArm.x(), 0.05);
  EXPECT_THAT(alignment.velocity_yaw_estimate->value, AngleNearDeg(kMounting.yaw, 0.1));
  EXPECT_THAT(alignment.yaw->value, AngleNearDeg(kMounting.yaw, 0.1));
}

// On a circle the yaw and the lever arm cannot be told apart: the turns are not used and the
// reason says why. Slow enough (6 m/s on 25 m) to pass the lateral-acceleration gate.
TEST(TrackAlignment, ACircleLeavesTheLeverArmUnidentifiedAndTheTurnsUnused) {
  const auto heading = [](double t) { return 6.0 * t / 25.0; };
  const auto speed = [](double) { return 6.0; };
  const TrackAlignment alignment = align_track(drive(40.0, heading, speed, kMounting, true));
  ASSERT_TRUE(alignment.insufficient_reason);
  EXPECT_FALSE(alignment.turns_used);
  ASSERT_TRUE(alignment.lever_arm_rejected);
  EXPECT_NE(alignment.insufficient_reason->find("turns not used"), std::string::npos)
      << *alignment.insufficient_reason;
}

TEST(TrackAlignment, TurnOptionsAreChecked) {
  TrackAlignmentOptions options;
  options.turns.max_lateral_acceleration = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.turns.lever_arm = Eigen::Vector3d(std::nan(""), 0.0, 0.0);
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(turn_samples_from_string("exclude"), TurnSamples::kExclude);
  EXPECT_EQ(to_string(TurnSamples::kUse), "use");
  EXPECT_THROW(turn_samples_from_string("sometimes"), std::invalid_argument);
}

}  // namespace
}  // namespace x2car
