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
    EXPECT_NEAR(alignment.valid_duration_s, 120.0 - 2 * 1.0, 0.05);  // trimmed 1 s at both ends
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
    const TrackAlignment alignment = align_track(with_time_jump(track, 60.0, jump_s));
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
