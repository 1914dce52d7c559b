#include "x2car/camera/camera_calibration.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::camera {
namespace {

using x2car::testing::AngleNearDeg;

const EulerAngles kMounting{rad_from_deg(1.5), rad_from_deg(3.0), rad_from_deg(-2.0)};

// A short drive down a straight street at 10 Hz (or `rate_hz`) and 10 m/s: the driver weaves in
// the lane (the road's heading against the car swings by +-0.05 deg), `turn_rate` [rad/s] turns
// the road's direction over time; the car stands for the first `stand_s` [s].
CameraFrameSource street_drive(std::size_t count, double turn_rate = 0.0, double stand_s = 0.0,
                               double rate_hz = 10.0) {
  CameraFrameSource frames;
  for (std::size_t i = 0; i < count; ++i)
    frames.times.push_back(100.0 + static_cast<double>(i) / rate_hz);
  frames.read = [turn_rate, stand_s, rate_hz](std::size_t index) {
    const double time = static_cast<double>(index) / rate_hz;
    testing::StreetScene scene;
    scene.vehicle_from_camera = kMounting;
    scene.travelled_m = 10.0 * std::max(0.0, time - stand_s);
    scene.road_heading = rad_from_deg(0.05) * std::sin(0.7 * time) + turn_rate * time;
    scene.noise_seed = index + 1;
    return testing::draw_street(scene, core::camera_preset("kitti"));
  };
  return frames;
}

// The exact vanishing point and horizon of a camera mounted at `mounting`, as an estimator's.
FrameEstimate exact_estimate(const EulerAngles& mounting, const core::CameraIntrinsics& camera) {
  const std::optional<VanishingGeometry> geometry =
      vanishing_geometry_from_rotation(rotation_from_euler(mounting), camera.camera_matrix());
  FrameEstimate estimate;
  estimate.road_vanishing_point_px = geometry->vanishing_point_px;
  estimate.horizon_line = geometry->horizon_line;
  return estimate;
}

// Counts the frames' decodes in `reads` (which must outlive the source).
void count_reads(CameraFrameSource& frames, std::atomic<int>& reads) {
  frames.read = [&reads, draw = frames.read](std::size_t index) {
    ++reads;
    return draw(index);
  };
}

CameraCalibrationOptions short_windows() {
  CameraCalibrationOptions options;
  options.filter.window_frames = 12;  // the paper's 100 at 10 Hz is 10 s; the tests drive ~4 s
  return options;
}

TEST(CalibrateCamera, RecoversTheMountingOfAStreetDrive) {
  const CameraFrameSource frames = street_drive(36);
  std::atomic<std::size_t> progress_calls = 0;
  CameraCalibrationOptions options = short_windows();
  options.progress = [&](std::size_t, std::size_t total) {
    EXPECT_EQ(total, 36U);
    ++progress_calls;
  };
  const CalibrationResult result = calibrate_camera(frames, core::camera_preset("kitti"), options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.sensor, "camera");
  EXPECT_EQ(result.method, "geometric");
  EXPECT_THAT(*result.roll, AngleNearDeg(kMounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(kMounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(kMounting.yaw, 0.1));
  EXPECT_EQ(result.support.at("windows"), 3);
  EXPECT_EQ(result.support.at("frames_in_windows"), 36);
  EXPECT_GE(*result.pitch_std, TemporalFilterOptions{}.standard_error_floor.pitch);
  // Gravity's horizon: the roll's standard error holds the road's crossfall, and the note says so.
  EXPECT_GE(*result.roll_std, CameraCalibrationOptions{}.gravity_horizon_roll_floor);
  EXPECT_THAT(result.reason, ::testing::HasSubstr("crossfall"));
  EXPECT_EQ(progress_calls.load(), 36U);
  // Per-frame series for plots: every frame estimated, all in windows; and the window motion
  // gate's readings, a point per window.
  ASSERT_FALSE(result.series.empty());
  for (const Series& series : result.series) {
    if (series.name.starts_with("window_")) {
      EXPECT_EQ(series.value.size(), 3U) << series.name;
      continue;
    }
    EXPECT_EQ(series.value.size(), 36U) << series.name;
    EXPECT_EQ(series.time.size(), 36U) << series.name;
  }
}

// Counts of frames given at 10 Hz hold as many seconds at the frames' own rate (the median
// interval: a dropped frame or a repeated time does not move it).
TEST(CalibrateCamera, FrameCountsAreScaledToTheFramesRate) {
  const CameraCalibrationOptions defaults;
  const auto times_at = [](double rate_hz, std::size_t count) {
    std::vector<double> times;
    for (std::size_t i = 0; i < count; ++i) times.push_back(5.0 + static_cast<double>(i) / rate_hz);
    return times;
  };
  std::vector<double> at_30_hz = times_at(30.0, 50);
  at_30_hz.erase(at_30_hz.begin() + 20);                 // a dropped frame
  at_30_hz.insert(at_30_hz.begin() + 30, at_30_hz[30]);  // a repeated time
  const CameraCalibrationOptions fast = options_at_frame_rate(defaults, at_30_hz);
  EXPECT_EQ(fast.filter.window_frames, 300);
  EXPECT_EQ(fast.filter.min_road_plane_frames, 99);
  EXPECT_EQ(fast.noisy_estimator_block_frames, 30);
  EXPECT_EQ(fast.motion_guide_frame_step, 30);
  const CameraCalibrationOptions slow = options_at_frame_rate(defaults, times_at(5.0, 10));
  EXPECT_EQ(slow.filter.window_frames, 50);
  EXPECT_NEAR(slow.filter.min_road_plane_frames, 16.5, 0.5);  // 33 halved, rounded either way
  EXPECT_EQ(slow.noisy_estimator_block_frames, 5);
  EXPECT_EQ(slow.motion_guide_frame_step, 5);
  // A very slow log keeps a window of 2 frames, a block and a step of 1.
  const CameraCalibrationOptions sparse = options_at_frame_rate(defaults, times_at(0.01, 3));
  EXPECT_EQ(sparse.filter.window_frames, 2);
  EXPECT_EQ(sparse.noisy_estimator_block_frames, 1);
  EXPECT_EQ(sparse.motion_guide_frame_step, 1);
  EXPECT_EQ(sparse.motion_frame_step, 1);
  EXPECT_NO_THROW(sparse.Check());
  // At most 10 Hz, 10 % over it allowed: every 3rd frame of 30, 30.3 and 33 Hz, every 2nd of 12
  // and 20 Hz, every frame at 11 Hz, at 10 Hz with a most of 30, and with none.
  EXPECT_EQ(frames_apart_for_rate(times_at(30.0, 20), 10.0), 3U);
  EXPECT_EQ(frames_apart_for_rate(times_at(30.3, 20), 10.0), 3U);
  EXPECT_EQ(frames_apart_for_rate(times_at(33.0, 20), 10.0), 3U);
  EXPECT_EQ(frames_apart_for_rate(times_at(12.0, 20), 10.0), 2U);
  EXPECT_EQ(frames_apart_for_rate(times_at(20.0, 20), 10.0), 2U);
  EXPECT_EQ(frames_apart_for_rate(times_at(11.0, 20), 10.0), 1U);
  EXPECT_EQ(frames_apart_for_rate(times_at(10.0, 20), 30.0), 1U);
  EXPECT_EQ(frames_apart_for_rate(times_at(30.0, 20), 0.0), 1U);
  EXPECT_EQ(frames_apart_for_rate({1.0}, 10.0), 1U);
  // The motion estimator's pairs span 0.1 s at any rate (half a step rounds up at 5 Hz).
  EXPECT_EQ(fast.motion_frame_step, 3);
  EXPECT_EQ(slow.motion_frame_step, 1);
  EXPECT_EQ(options_at_frame_rate(defaults, times_at(60.0, 20)).motion_frame_step, 6);
  CameraCalibrationOptions no_step = defaults;
  no_step.motion_frame_step = 0;
  EXPECT_THROW(no_step.Check(), std::invalid_argument);
  // The filter's own blocks (1: the paper's test on each frame) keep their count, at most half
  // the window: a caller's 10 against a window of 10 at 1 Hz.
  EXPECT_EQ(fast.filter.steadiness_block_frames, 1);
  CameraCalibrationOptions blocks = defaults;
  blocks.filter.steadiness_block_frames = 10;
  const CameraCalibrationOptions at_1_hz = options_at_frame_rate(blocks, times_at(1.0, 10));
  EXPECT_EQ(at_1_hz.filter.window_frames, 10);
  EXPECT_EQ(at_1_hz.filter.steadiness_block_frames, 5);
  EXPECT_EQ(options_at_frame_rate(blocks, at_30_hz).filter.steadiness_block_frames, 10);
  EXPECT_NO_THROW(at_1_hz.Check());
  // A window given at any rate; the rest still follows the rate.
  CameraCalibrationOptions given = defaults;
  given.window_frames_at_any_rate = 12;
  const CameraCalibrationOptions given_at_30_hz = options_at_frame_rate(given, at_30_hz);
  EXPECT_EQ(given_at_30_hz.filter.window_frames, 12);
  EXPECT_EQ(given_at_30_hz.noisy_estimator_block_frames, 30);
  EXPECT_EQ(given_at_30_hz.motion_guide_frame_step, 30);
  EXPECT_EQ(options_at_frame_rate(given, times_at(10.0, 20)).filter.window_frames, 12);
  given.window_frames_at_any_rate = 1;
  EXPECT_THROW(given.Check(), std::invalid_argument);
  // Intervals that alternate (a stream published in bursts), 1/30 s three times and 1/20 s twice,
  // are 25 Hz, not the median's 30; two and three times, 23.1 Hz, not 20. A stop in the recording
  // does not count.
  const auto bursts = [](int short_intervals) {
    std::vector<double> times{0.0};
    for (int i = 0; i < 60; ++i) {
      times.push_back(times.back() + (i % 5 < short_intervals ? 1.0 / 30 : 1.0 / 20));
    }
    times.push_back(times.back() + 2.0);
    return times;
  };
  EXPECT_EQ(options_at_frame_rate(defaults, bursts(3)).filter.window_frames, 250);
  EXPECT_EQ(options_at_frame_rate(defaults, bursts(2)).filter.window_frames, 231);
  // KITTI's own camera (0.1036 s by its timestamps) keeps the paper's n; 11.5 Hz does not.
  EXPECT_EQ(options_at_frame_rate(defaults, times_at(1.0 / 0.1036, 20)).filter.window_frames, 100);
  EXPECT_EQ(options_at_frame_rate(defaults, times_at(11.5, 20)).filter.window_frames, 115);
  // As given: at 10 Hz, with one frame, without the rate, and a first look that is off.
  EXPECT_EQ(options_at_frame_rate(defaults, times_at(10.0, 20)).filter.window_frames, 100);
  EXPECT_EQ(options_at_frame_rate(defaults, {3.0}).filter.window_frames, 100);
  CameraCalibrationOptions as_given = defaults;
  as_given.filter_frame_rate_hz = 0.0;
  EXPECT_EQ(options_at_frame_rate(as_given, at_30_hz).filter.window_frames, 100);
  CameraCalibrationOptions no_look = defaults;
  no_look.motion_guide_frame_step = 0;
  EXPECT_EQ(options_at_frame_rate(no_look, at_30_hz).motion_guide_frame_step, 0);
}

// The paper's window is 100 frames of a 10 Hz camera, 10 s of road; at another frame rate a
// window holds as many seconds (filter_frame_rate_hz), not as many frames: a 30 Hz video windowed
// by frame count passed windows of a third of the time through curves and accelerations. Here 12
// frames at 10 Hz (short_windows) are 36 at 30 Hz and 6 at 5 Hz: three windows in each 3.6-s
// drive; with the counts as given, nine at 30 Hz.
TEST(CalibrateCamera, WindowsHoldAsManySecondsAtAnyFrameRate) {
  const core::CameraIntrinsics camera = core::camera_preset("kitti");
  const CalibrationResult at_10_hz = calibrate_camera(street_drive(36), camera, short_windows());
  ASSERT_TRUE(at_10_hz.ok()) << at_10_hz.reason;
  EXPECT_EQ(at_10_hz.support.at("windows"), 3);
  EXPECT_FALSE(at_10_hz.diagnostics.contains("window_frames"));

  const CalibrationResult at_30_hz =
      calibrate_camera(street_drive(108, 0.0, 0.0, 30.0), camera, short_windows());
  ASSERT_TRUE(at_30_hz.ok()) << at_30_hz.reason;
  EXPECT_EQ(at_30_hz.support.at("windows"), 3);
  EXPECT_EQ(at_30_hz.support.at("frames_in_windows"), 108);
  EXPECT_EQ(at_30_hz.diagnostics.at("window_frames"), 36.0);
  EXPECT_THAT(*at_30_hz.yaw, AngleNearDeg(kMounting.yaw, 0.1));

  const CalibrationResult at_5_hz =
      calibrate_camera(street_drive(18, 0.0, 0.0, 5.0), camera, short_windows());
  ASSERT_TRUE(at_5_hz.ok()) << at_5_hz.reason;
  EXPECT_EQ(at_5_hz.support.at("windows"), 3);
  EXPECT_EQ(at_5_hz.diagnostics.at("window_frames"), 6.0);

  // A second of 30 Hz frames is too short for a window of 1.2 s, and the reason counts frames.
  const CalibrationResult short_drive =
      calibrate_camera(street_drive(30, 0.0, 0.0, 30.0), camera, short_windows());
  EXPECT_EQ(short_drive.status, CalibrationStatus::kInsufficientData);
  EXPECT_THAT(short_drive.reason, ::testing::HasSubstr("need 36"));

  CameraCalibrationOptions as_given = short_windows();
  as_given.filter_frame_rate_hz = 0.0;
  const CalibrationResult frames_as_given =
      calibrate_camera(street_drive(108, 0.0, 0.0, 30.0), camera, as_given);
  ASSERT_TRUE(frames_as_given.ok()) << frames_as_given.reason;
  EXPECT_EQ(frames_as_given.support.at("windows"), 9);
  EXPECT_FALSE(frames_as_given.diagnostics.contains("window_frames"));

  CameraCalibrationOptions bad = short_windows();
  bad.filter_frame_rate_hz = -1.0;
  EXPECT_THROW(calibrate_camera(street_drive(36), camera, bad), std::invalid_argument);
}

// max_frame_rate_hz: of a 30 Hz drive at 10 Hz every 3rd frame is decoded and estimated, and the
// run goes on at 10 Hz (windows of the counts as given); a frame keeps its own name in errors.
TEST(CalibrateCamera, AFastCameraCanBeTakenAtALowerFrameRate) {
  const core::CameraIntrinsics camera = core::camera_preset("kitti");
  CameraFrameSource frames = street_drive(108, 0.0, 0.0, 30.0);
  std::atomic<int> reads = 0;
  count_reads(frames, reads);
  CameraCalibrationOptions options = short_windows();
  options.max_frame_rate_hz = 10.0;
  options.refuse_standing = false;  // their own reads are not the run's
  options.gate_window_motion = false;
  options.facing = CameraFacing::kAhead;
  std::atomic<std::size_t> last_total = 0;
  options.progress = [&](std::size_t, std::size_t total) { last_total = total; };
  const CalibrationResult result = calibrate_camera(frames, camera, options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(reads.load(), 36);
  EXPECT_EQ(last_total.load(), 36U);
  EXPECT_EQ(result.support.at("frames"), 36);
  EXPECT_EQ(result.support.at("frames_skipped_for_rate"), 72);
  EXPECT_EQ(result.diagnostics.at("frames_apart"), 3.0);
  EXPECT_FALSE(result.diagnostics.contains("window_frames"));  // 12 frames at 10 Hz
  EXPECT_EQ(result.support.at("windows"), 3);
  EXPECT_THAT(*result.roll, AngleNearDeg(kMounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(kMounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(kMounting.yaw, 0.1));
  ASSERT_FALSE(result.series.empty());
  EXPECT_DOUBLE_EQ(result.series.front().time[1], frames.times[3]);
  // Rates at or below the most take every frame.
  options.max_frame_rate_hz = 30.0;
  EXPECT_FALSE(
      calibrate_camera(street_drive(36), camera, options).diagnostics.contains("frames_apart"));
  // A frame that cannot be read is named by its place in the source (frame 30, the 11th kept).
  frames.read = [draw = frames.read](std::size_t index) {
    return index == 30 ? cv::Mat() : draw(index);
  };
  options.max_frame_rate_hz = 10.0;
  try {
    calibrate_camera(frames, camera, options);
    ADD_FAILURE() << "an unreadable frame passed";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("frame 30"));
  }
  options.max_frame_rate_hz = -1.0;
  EXPECT_THROW(calibrate_camera(frames, camera, options), std::invalid_argument);
  // Kept frames too far apart for the run's pairs are refused, naming what pairs them: the motion
  // estimator's 0.25 s at 3 Hz (every 10th, 0.33 s), the facing check's 0.5 s at 1.5 Hz.
  const auto refusal = [&](const CameraCalibrationOptions& refused) -> std::string {
    try {
      calibrate_camera(frames, camera, refused);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "not refused";
  };
  options.max_frame_rate_hz = 3.0;
  options.method = CameraMethod::kMotion;
  EXPECT_THAT(refusal(options), ::testing::HasSubstr("max_pair_gap_s"));
  options.method = CameraMethod::kGeometric;
  options.max_frame_rate_hz = 1.5;
  options.facing = CameraFacing::kFromMotion;
  EXPECT_THAT(refusal(options), ::testing::HasSubstr("facing_pair_max_gap_s"));
}

// A car standing at a light passes the window's steadiness test without driving: one view
// repeated, the smallest spread and so the largest weight of all. The images show it stood, and
// the window is refused and counted (before, a car that never moved calibrated `ok`). Without
// the car's motion only; with it, its speed gates such frames.
TEST(CalibrateCamera, WindowsTheCarStoodThroughAreRefused) {
  const CalibrationResult standing =
      calibrate_camera(street_drive(36, 0.0, 10.0), core::camera_preset("kitti"), short_windows());
  EXPECT_EQ(standing.status, CalibrationStatus::kInsufficientData);
  EXPECT_THAT(
      standing.reason,
      ::testing::HasSubstr("the car stood through 3 steady windows of 12 frames, all there were"));
  EXPECT_EQ(standing.support.at("windows_refused_standing"), 3);
  EXPECT_FALSE(standing.roll || standing.pitch || standing.yaw);

  const CalibrationResult drives_off =
      calibrate_camera(street_drive(36, 0.0, 1.2), core::camera_preset("kitti"), short_windows());
  ASSERT_TRUE(drives_off.ok()) << drives_off.reason;
  EXPECT_EQ(drives_off.support.at("windows"), 2);
  EXPECT_EQ(drives_off.support.at("windows_refused_standing"), 1);
  EXPECT_THAT(*drives_off.yaw, AngleNearDeg(kMounting.yaw, 0.1));

  CameraCalibrationOptions kept = short_windows();
  kept.refuse_standing = false;
  EXPECT_TRUE(
      calibrate_camera(street_drive(36, 0.0, 10.0), core::camera_preset("kitti"), kept).ok());

  // Windows whose every frame had the car's motion are not looked at: its speed gate kept
  // standing frames out (here the log says 10 m/s over frames that do not move).
  CameraFrameSource logged = street_drive(36, 0.0, 10.0);
  logged.motion.assign(36, VehicleMotion{.speed_mps = 10.0});
  const CalibrationResult moving =
      calibrate_camera(logged, core::camera_preset("kitti"), short_windows());
  ASSERT_TRUE(moving.ok()) << moving.reason;
  EXPECT_EQ(moving.support.count("windows_refused_standing"), 0U);
}

// A camera that looks back sees the road's vanishing point where one that looks ahead does: only
// the motion tells them apart (the scene flows into the vanishing point behind a car that drives
// on). The rear camera's yaw comes back turned by 180 deg, roll and pitch as they are, with a note;
// before, it came back ok with its yaw 180 deg wrong. The front camera on the same drive stays.
TEST(CalibrateCamera, ACameraThatLooksBackIsFoundByTheImagesMotion) {
  const EulerAngles rear_mounting{rad_from_deg(0.6), rad_from_deg(1.5),
                                  wrap_angle(kPi + rad_from_deg(1.2))};
  const auto drive = [](const EulerAngles& mounting, const Eigen::Vector3d& position) {
    CameraFrameSource frames;
    for (std::size_t i = 0; i < 24; ++i) frames.times.push_back(0.1 * static_cast<double>(i));
    frames.read = [mounting, position](std::size_t index) {
      testing::StreetScene scene;
      scene.vehicle_from_camera = mounting;
      scene.camera_in_vehicle = position;
      scene.world_behind = true;
      scene.travelled_m = 0.8 * static_cast<double>(index);  // 8 m/s
      scene.noise_seed = index + 1;
      return testing::draw_street(scene, core::camera_preset("kitti"));
    };
    return frames;
  };
  const CalibrationResult rear = calibrate_camera(drive(rear_mounting, {-0.9, 0.0, 1.2}),
                                                  core::camera_preset("kitti"), short_windows());
  ASSERT_TRUE(rear.ok()) << rear.reason;
  EXPECT_THAT(*rear.roll, AngleNearDeg(rear_mounting.roll, 0.1));
  EXPECT_THAT(*rear.pitch, AngleNearDeg(rear_mounting.pitch, 0.1));
  EXPECT_THAT(*rear.yaw, AngleNearDeg(rear_mounting.yaw, 0.1));
  EXPECT_THAT(rear.reason, ::testing::HasSubstr("the camera looks back"));
  EXPECT_GT(rear.support.at("facing_pairs_flowing_in"), 0);
  EXPECT_EQ(rear.support.at("facing_pairs_flowing_out"), 0);

  const EulerAngles front_mounting{rad_from_deg(0.6), rad_from_deg(1.5), rad_from_deg(1.2)};
  const CalibrationResult front = calibrate_camera(drive(front_mounting, {1.5, 0.0, 1.4}),
                                                   core::camera_preset("kitti"), short_windows());
  ASSERT_TRUE(front.ok()) << front.reason;
  EXPECT_THAT(*front.yaw, AngleNearDeg(front_mounting.yaw, 0.1));
  EXPECT_THAT(front.reason, ::testing::Not(::testing::HasSubstr("looks back")));
  EXPECT_GT(front.support.at("facing_pairs_flowing_out"), 0);
  EXPECT_EQ(front.support.at("facing_pairs_flowing_in"), 0);

  // The rear camera's per-frame yaws are turned alike (the series for plots).
  for (const Series& series : rear.series) {
    if (series.name != "frame_yaw") continue;
    ASSERT_FALSE(series.value.empty());
    EXPECT_THAT(series.value.front(), AngleNearDeg(rear_mounting.yaw, 0.3));
  }

  // Given ahead (the old assumption), the rear camera's yaw is 180 deg away; given back, right.
  CameraCalibrationOptions given = short_windows();
  given.facing = CameraFacing::kAhead;
  const CalibrationResult assumed =
      calibrate_camera(drive(rear_mounting, {-0.9, 0.0, 1.2}), core::camera_preset("kitti"), given);
  ASSERT_TRUE(assumed.ok()) << assumed.reason;
  EXPECT_THAT(*assumed.yaw, AngleNearDeg(wrap_angle(rear_mounting.yaw + kPi), 0.1));
  given.facing = CameraFacing::kBack;
  const CalibrationResult told =
      calibrate_camera(drive(rear_mounting, {-0.9, 0.0, 1.2}), core::camera_preset("kitti"), given);
  ASSERT_TRUE(told.ok()) << told.reason;
  EXPECT_THAT(*told.yaw, AngleNearDeg(rear_mounting.yaw, 0.1));
  EXPECT_THAT(told.reason, ::testing::HasSubstr("looks back (given)"));

  // A street that does not move (the car standing; its windows kept): taken as looking ahead,
  // and said.
  CameraCalibrationOptions standing_kept = short_windows();
  standing_kept.refuse_standing = false;
  const CalibrationResult standing =
      calibrate_camera(street_drive(24, 0.0, 10.0), core::camera_preset("kitti"), standing_kept);
  ASSERT_TRUE(standing.ok()) << standing.reason;
  EXPECT_THAT(standing.reason, ::testing::HasSubstr("taken as looking ahead"));
}

// A road that keeps turning: the vanishing point wanders and no window is steady. Insufficient
// data with a reason, never a number.
TEST(CalibrateCamera, ACurvingRoadGivesNoNumber) {
  const CameraFrameSource frames = street_drive(26, rad_from_deg(3.0));
  const CalibrationResult result =
      calibrate_camera(frames, core::camera_preset("kitti"), short_windows());
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_FALSE(result.roll.has_value());
  EXPECT_NE(result.reason.find("no window of 12 frames was steady"), std::string::npos)
      << result.reason;
}

// A steady acceleration pitches the body through a whole window, and only the car's motion shows
// it: without the motion the pitch's standard error holds a floor for it, and the note says so.
TEST(CalibrateCamera, WithoutTheCarsMotionThePitchStandardErrorHoldsTheBodysPitch) {
  const CameraCalibrationOptions options = short_windows();
  CameraFrameSource frames = street_drive(36);
  const CalibrationResult alone = calibrate_camera(frames, core::camera_preset("kitti"), options);
  ASSERT_TRUE(alone.ok()) << alone.reason;
  EXPECT_GE(*alone.pitch_std, options.unknown_motion_pitch_floor);
  EXPECT_THAT(alone.reason, ::testing::HasSubstr("--ins"));
  frames.motion.assign(36, VehicleMotion{10.0, 0.0});
  const CalibrationResult gated = calibrate_camera(frames, core::camera_preset("kitti"), options);
  ASSERT_TRUE(gated.ok()) << gated.reason;
  EXPECT_LT(*gated.pitch_std, options.unknown_motion_pitch_floor);
  EXPECT_THAT(gated.reason, ::testing::Not(::testing::HasSubstr("--ins")));
  EXPECT_DOUBLE_EQ(*gated.pitch, *alone.pitch);
}

// `--ins` over only part of the drive: the windows outside the log still lack the car's motion,
// and their share of the floor stays in the pitch's standard error (it was dropped whenever any
// frame had a motion), with a note that says how many windows.
TEST(CalibrateCamera, MotionOverPartOfTheDriveKeepsTheFloorForTheWindowsWithout) {
  const CameraCalibrationOptions options = short_windows();
  CameraFrameSource frames = street_drive(36);
  frames.motion.assign(36, std::nullopt);
  for (std::size_t i = 0; i < 24; ++i) frames.motion[i] = VehicleMotion{10.0, 0.0};
  const CalibrationResult partial = calibrate_camera(frames, core::camera_preset("kitti"), options);
  ASSERT_TRUE(partial.ok()) << partial.reason;
  ASSERT_EQ(partial.support.at("windows"), 3);
  // The floor is scaled by the weight that window carries in the pitch's mean (about a third).
  const double floor_deg = partial.diagnostics.at("unknown_motion_pitch_floor_deg");
  EXPECT_GT(floor_deg, deg_from_rad(options.unknown_motion_pitch_floor) * 0.2);
  EXPECT_LT(floor_deg, deg_from_rad(options.unknown_motion_pitch_floor) * 0.5);
  EXPECT_GE(*partial.pitch_std, rad_from_deg(floor_deg));
  EXPECT_LT(*partial.pitch_std, options.unknown_motion_pitch_floor);
  EXPECT_THAT(partial.reason, ::testing::HasSubstr("in 1 of the 3 steady windows (--ins"));
}

// With the car's motion known, turning and slow frames are never decoded and are counted.
TEST(CalibrateCamera, GatesByTheCarsMotionBeforeDecoding) {
  CameraFrameSource frames = street_drive(30);
  std::atomic<int> decoded = 0;
  count_reads(frames, decoded);
  for (std::size_t i = 0; i < 30; ++i) {
    frames.motion.push_back(i < 10 ? VehicleMotion{1.0, 0.0} : VehicleMotion{10.0, 0.3});
  }
  const CalibrationResult result =
      calibrate_camera(frames, core::camera_preset("kitti"), short_windows());
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(result.reason, "only 0 frames in stable stretches; need 12");
  EXPECT_EQ(result.rejections.at("slow"), 10);
  EXPECT_EQ(result.rejections.at("turning"), 20);
  EXPECT_EQ(decoded.load(), 0);
}

TEST(CalibrateCamera, AnImageOfTheWrongSizeNamesTheFrame) {
  CameraFrameSource frames = street_drive(5);
  frames.read = [](std::size_t) { return cv::Mat(100, 200, CV_8UC1, cv::Scalar(0)); };
  frames.name = [](std::size_t index) { return fmt::format("images/{:010d}.png", index); };
  try {
    calibrate_camera(frames, core::camera_preset("kitti"), short_windows());
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "images/0000000000.png");
    EXPECT_EQ(error.field(), "image size");
    EXPECT_NE(std::string(error.what()).find("200x100"), std::string::npos) << error.what();
  }
}

TEST(CalibrateCamera, UnreadableImagesEndTheRunOrAreCounted) {
  CameraFrameSource frames = street_drive(3);
  frames.read = [](std::size_t index) -> cv::Mat {
    throw InputError(fmt::format("images/{}.png", index), "not a PNG");
  };
  EXPECT_THROW(calibrate_camera(frames, core::camera_preset("kitti"), short_windows()), InputError);
  CameraCalibrationOptions options = short_windows();
  options.skip_bad_images = true;
  const CalibrationResult result = calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(result.rejections.at("unreadable_image"), 3);
  EXPECT_NE(result.reason.find("images/0.png"), std::string::npos) << result.reason;
}

TEST(CalibrateCamera, BlankFramesAreCountedByReason) {
  CameraFrameSource frames = street_drive(4);
  frames.read = [](std::size_t) { return cv::Mat(375, 1242, CV_8UC1, cv::Scalar(90)); };
  const CalibrationResult result =
      calibrate_camera(frames, core::camera_preset("kitti"), short_windows());
  EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(result.rejections.at("too_few_lines"), 4);
}

// The motion estimator follows each frame's road back through the frames before it (3 frames in
// all): the first two frames, and those whose span holds a gap longer than max_pair_gap_s, have
// too few. The car stands, so the pairs that are made see no travel: a reason for every frame,
// never a number.
TEST(CalibrateCamera, MotionPairsFramesAndCountsWhyNot) {
  CameraFrameSource frames = street_drive(6, 0.0, 10.0);
  frames.times[3] += 0.5;  // a gap between frames 2 and 3: frames 3 and 4 span it
  frames.times[4] += 0.5;
  frames.times[5] += 0.5;
  for (const CameraMethod method : {CameraMethod::kMotion, CameraMethod::kAuto}) {
    CameraCalibrationOptions options = short_windows();
    options.method = method;
    options.motion.tracked_frames = 3;
    const CalibrationResult result =
        calibrate_camera(frames, core::camera_preset("kitti"), options);
    EXPECT_EQ(result.status, CalibrationStatus::kInsufficientData);
    EXPECT_EQ(result.method, to_string(method));
    if (method == CameraMethod::kMotion) {
      EXPECT_EQ(result.rejections.at("no_previous_frame"), 4);
      int counted = 0;
      for (const auto& [reason, count] : result.rejections) counted += static_cast<int>(count);
      EXPECT_EQ(counted, 6);
      EXPECT_EQ(result.support.at("usable_frames"), 0);
    } else {
      // auto keeps the lines' frames; the pairs' failures are counted beside them.
      EXPECT_TRUE(result.rejections.empty());
      EXPECT_EQ(result.support.at("usable_frames"), 6);
      EXPECT_EQ(result.support.at("road_plane_no_previous_frame"), 4);
    }
  }
  CameraCalibrationOptions bad;
  bad.method = CameraMethod::kMotion;
  bad.motion.min_inliers = 2;
  EXPECT_THROW(calibrate_camera(frames, core::camera_preset("kitti"), bad), std::invalid_argument);
}

// The motion estimator pairs each frame with the one before it, and frames are estimated in
// parallel: each frame is decoded once for both turns (the calibrator keeps the frames decoded
// last), not twice. The first look (every 4th frame here) decodes its frames and the ones before
// them first, all over the drive; they must not crowd the run's frames out of the cache, and the
// run reads them again from where the first look kept them (first_look_kept_bytes).
TEST(CalibrateCamera, MotionDecodesEachFrameOnce) {
  CameraFrameSource frames = street_drive(40);
  const cv::Mat first_frame = frames.read(0);
  const std::size_t frame_bytes = first_frame.total() * first_frame.elemSize();
  std::atomic<int> reads = 0;
  count_reads(frames, reads);
  CameraCalibrationOptions options = short_windows();
  options.method = CameraMethod::kMotion;
  options.motion_guide_frame_step = 4;
  options.detect_car_region = false;  // its own reads are counted below
  const CalibrationResult once = calibrate_camera(frames, core::camera_preset("kitti"), options);
  // Without the cache: the first look's 2 x 10, then 40 + 39 = 99; with it 20 + 40 = 60, and a few
  // more when two threads miss the same frame at once (evicting the lowest index instead of the
  // oldest: 72); with the first look's frames kept for the run, 40 and those few.
  EXPECT_GE(reads.load(), 40);
  EXPECT_LE(reads.load(), 44);
  // Room for 5 of the first look's 20 frames: the run decodes the other 15 again (none kept: 60).
  // Kept or decoded again, the frames are the same: so is the result.
  reads = 0;
  options.first_look_kept_bytes = 5 * frame_bytes;
  const CalibrationResult again = calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_GE(reads.load(), 55);
  EXPECT_LE(reads.load(), 59);
  EXPECT_EQ(again.status, once.status);
  EXPECT_EQ(again.roll, once.roll);
  EXPECT_EQ(again.pitch, once.pitch);
  EXPECT_EQ(again.yaw, once.yaw);
  // Looking for the car's body first decodes its samples once more.
  reads = 0;
  options.first_look_kept_bytes = CameraCalibrationOptions{}.first_look_kept_bytes;
  options.detect_car_region = true;
  calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_GE(reads.load(), 40 + options.car_region.sample_frames);
  EXPECT_LE(reads.load(), 44 + options.car_region.sample_frames);
}

// At 30 Hz the frame before is a third of the 10 Hz pair's travel away, and so is the road's
// parallax: the motion estimator pairs each frame with the one 0.1 s before it
// (CameraCalibrationOptions::motion_frame_step, scaled with the rate), and still decodes each frame
// once, the first look's frames included. A pair reaches 3 frames back: the first 3 frames have
// none, nor have the 3 after a gap in the recording, nor the 3 whose pair frames dropped frames
// stretch beyond max_pair_gap_s (0.1 s between neighbours, 0.3 s between the pair).
TEST(CalibrateCamera, MotionPairsSpanATenthOfASecondAtAnyFrameRate) {
  CameraFrameSource frames = street_drive(45, 0.0, 0.0, 30.0);
  for (std::size_t i = 20; i < frames.times.size(); ++i) frames.times[i] += 0.5;
  for (std::size_t i = 31; i < frames.times.size(); ++i) {
    frames.times[i] += 0.2 / 3.0 * static_cast<double>(std::min<std::size_t>(i - 30, 5));
  }
  std::atomic<int> reads = 0;
  count_reads(frames, reads);
  CameraCalibrationOptions options = short_windows();
  options.method = CameraMethod::kMotion;
  options.motion_guide_frame_step = 4;  // 12 at 30 Hz: frames 11, 23 and 35 and their pairs
  options.detect_car_region = false;
  const CalibrationResult paired = calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_EQ(paired.diagnostics.at("motion_frame_step"), 3.0);
  EXPECT_EQ(paired.rejections.at("no_previous_frame"), 3 + 3 + 3);
  EXPECT_GE(reads.load(), 45);
  EXPECT_LE(reads.load(), 49);
  // Consecutive frames (the counts as given): one frame at the start and one after the gap.
  options.filter_frame_rate_hz = 0.0;
  const CalibrationResult consecutive =
      calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_FALSE(consecutive.diagnostics.contains("motion_frame_step"));
  EXPECT_EQ(consecutive.rejections.at("no_previous_frame"), 1 + 1);
  // A step given at 10 Hz is scaled alike: 2 -> 6 frames back at 30 Hz.
  options.filter_frame_rate_hz = CameraCalibrationOptions{}.filter_frame_rate_hz;
  options.motion_frame_step = 2;
  const CalibrationResult longer = calibrate_camera(frames, core::camera_preset("kitti"), options);
  EXPECT_EQ(longer.diagnostics.at("motion_frame_step"), 6.0);
  EXPECT_GE(longer.rejections.at("no_previous_frame"), 6 + 6);
}

// A video decodes forward only and keeps its last few frames (video_frames.hpp): a frame asked for
// behind them starts the decoder again from the first frame. The first look must ask for its frames
// in order as the run does, not in the order its threads reach them: out of order, a one-minute
// video was decoded some twenty times over.
TEST(CalibrateCamera, MotionReadsAVideoForwardOnly) {
  CameraFrameSource frames = street_drive(40);
  struct ForwardDecoder {
    std::mutex mutex;
    std::size_t next = 0;  // the frame it decodes next
    int restarts = 0;
  };
  auto decoder = std::make_shared<ForwardDecoder>();
  constexpr std::size_t kKeptFrames = 8;
  frames.read = [decoder, draw = frames.read](std::size_t index) {
    {
      const std::lock_guard lock(decoder->mutex);
      if (index + kKeptFrames < decoder->next) {
        ++decoder->restarts;
        decoder->next = 0;
      }
      decoder->next = std::max(decoder->next, index + 1);
    }
    return draw(index);
  };
  CameraCalibrationOptions options = short_windows();
  options.method = CameraMethod::kMotion;
  options.motion_guide_frame_step = 4;
  calibrate_camera(frames, core::camera_preset("kitti"), options);
  // The car region's samples from the first frame on, then the first look, then the run: two
  // starts again.
  EXPECT_LE(decoder->restarts, 2);
}

TEST(CalibrateCamera, RejectsABadSourceOrOptions) {
  CameraFrameSource frames = street_drive(3);
  frames.times[2] = frames.times[1];
  EXPECT_THROW(calibrate_camera(frames, core::camera_preset("kitti")), std::invalid_argument);
  frames = street_drive(3);
  frames.motion.resize(2);
  EXPECT_THROW(calibrate_camera(frames, core::camera_preset("kitti")), std::invalid_argument);
  CameraCalibrationOptions options;
  options.max_window_disagreement = -1.0;
  EXPECT_THROW(calibrate_camera(street_drive(3), core::camera_preset("kitti"), options),
               std::invalid_argument);
}

// Any estimator plugs in: this one reads the frame's geometry off the image's first pixel (the
// frame index) and reports the exact VP and HL of mounting A for the first window and of B, 1 deg
// of yaw away, for the second. Both windows are steady but disagree: unreliable, angles kept.
TEST(CalibrateCamera, WindowsThatDisagreeAreUnreliable) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  CameraFrameSource frames;
  for (int i = 0; i < 24; ++i) frames.times.push_back(0.1 * i);
  frames.read = [&intrinsics](std::size_t index) {
    return cv::Mat(intrinsics.height, intrinsics.width, CV_8UC1,
                   cv::Scalar(static_cast<double>(index)));
  };
  CameraCalibrationOptions options = short_windows();
  options.estimator_name = "exact";
  options.estimator = [](const cv::Mat& image, const core::CameraIntrinsics& camera) {
    const bool second = image.at<std::uint8_t>(0, 0) >= 12;
    const EulerAngles mounting{kMounting.roll, kMounting.pitch,
                               kMounting.yaw + (second ? rad_from_deg(1.0) : 0.0)};
    return exact_estimate(mounting, camera);
  };
  const CalibrationResult result = calibrate_camera(frames, intrinsics, options);
  EXPECT_EQ(result.status, CalibrationStatus::kUnreliable);
  EXPECT_EQ(result.method, "exact");
  EXPECT_NE(result.reason.find("disagree"), std::string::npos) << result.reason;
  ASSERT_TRUE(result.yaw.has_value());
  EXPECT_NEAR(*result.yaw, kMounting.yaw + rad_from_deg(0.5), 1e-9);  // equal weights
  EXPECT_NEAR(*result.pitch, kMounting.pitch, 1e-9);
  EXPECT_NEAR(result.diagnostics.at("window_spread_yaw_deg"), 1.0, 1e-9);
}

// A caller's estimator (the learned network) may be wrong by the same amount for seconds: one
// steady window, however steady, gives no number; two that agree do.
TEST(CalibrateCamera, ACallersEstimatorNeedsTwoWindows) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  CameraFrameSource frames;
  for (int i = 0; i < 18; ++i) frames.times.push_back(0.1 * i);
  frames.read = [&intrinsics](std::size_t) {
    return cv::Mat(intrinsics.height, intrinsics.width, CV_8UC1, cv::Scalar(0));
  };
  CameraCalibrationOptions options = short_windows();
  options.estimator_name = "exact";
  options.estimator = [](const cv::Mat&, const core::CameraIntrinsics& camera) {
    return exact_estimate(kMounting, camera);
  };
  const CalibrationResult one_window = calibrate_camera(frames, intrinsics, options);
  EXPECT_EQ(one_window.status, CalibrationStatus::kInsufficientData);
  EXPECT_THAT(one_window.reason,
              ::testing::HasSubstr("only 1 steady window; the exact estimator needs 2"));
  EXPECT_FALSE(one_window.roll || one_window.pitch || one_window.yaw);
  EXPECT_EQ(one_window.support.at("windows"), 1);

  for (int i = 18; i < 24; ++i) frames.times.push_back(0.1 * i);
  const CalibrationResult two_windows = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(two_windows.ok()) << two_windows.reason;
  EXPECT_THAT(*two_windows.yaw, AngleNearDeg(kMounting.yaw, 1e-9));

  // What its windows share, no spread shows: its floor is in every standard error.
  options.estimator_standard_error_floor = {rad_from_deg(0.45), rad_from_deg(0.2), 0.0};
  const CalibrationResult floored = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(floored.ok()) << floored.reason;
  EXPECT_DOUBLE_EQ(*floored.roll_std, std::hypot(*two_windows.roll_std, rad_from_deg(0.45)));
  EXPECT_DOUBLE_EQ(*floored.pitch_std, std::hypot(*two_windows.pitch_std, rad_from_deg(0.2)));
  EXPECT_DOUBLE_EQ(*floored.yaw_std, *two_windows.yaw_std);
  EXPECT_DOUBLE_EQ(floored.diagnostics.at("estimator_standard_error_floor_roll_deg"), 0.45);
  EXPECT_DOUBLE_EQ(floored.diagnostics.at("estimator_standard_error_floor_pitch_deg"), 0.2);
  EXPECT_DOUBLE_EQ(floored.diagnostics.at("estimator_standard_error_floor_yaw_deg"), 0.0);
  EXPECT_THAT(floored.reason, ::testing::HasSubstr("exact estimator's own error on a drive"));
}

// An estimator whose angles scatter by 0.5 deg a frame, with no memory (a learned one's), and that
// fails on every seventh frame: the paper's test on each frame never passes, and a failed frame
// ends its stretch. Marked `estimator_scatters`, its windows are tested on blocks of frames and its
// failures leave holes: it calibrates, to the mean's accuracy.
TEST(CalibrateCamera, AnEstimatorThatScattersIsFilteredOnBlocksOfFrames) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  CameraFrameSource frames;
  for (int i = 0; i < 300; ++i) frames.times.push_back(0.1 * i);
  frames.read = [&intrinsics](std::size_t index) {
    cv::Mat image(intrinsics.height, intrinsics.width, CV_16UC1, cv::Scalar(0));
    image.at<std::uint16_t>(0, 0) = static_cast<std::uint16_t>(index);
    return image;
  };
  CameraCalibrationOptions options;
  options.estimator_name = "noisy";
  options.estimator = [](const cv::Mat& image, const core::CameraIntrinsics& camera) {
    const int index = image.at<std::uint16_t>(0, 0);
    if (index % 7 == 6) return rejected_frame(FrameRejection::kTooFewLines);
    std::mt19937_64 random(static_cast<std::uint64_t>(index));
    std::normal_distribution<double> noise(0.0, rad_from_deg(0.5));
    const EulerAngles angles{kMounting.roll + noise(random), kMounting.pitch + noise(random),
                             kMounting.yaw + noise(random)};
    return exact_estimate(angles, camera);
  };
  const CalibrationResult frame_by_frame = calibrate_camera(frames, intrinsics, options);
  EXPECT_EQ(frame_by_frame.status, CalibrationStatus::kInsufficientData);
  EXPECT_EQ(frame_by_frame.support.at("longest_stretch"), 6);
  EXPECT_EQ(frame_by_frame.diagnostics.count("steadiness_block_frames"), 0U);

  options.estimator_scatters = true;
  const CalibrationResult result = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.support.at("windows"), 2);
  EXPECT_EQ(result.support.at("usable_frames"), 258);
  EXPECT_EQ(result.diagnostics.at("steadiness_block_frames"), 10.0);
  // 200 frames of 0.5 deg: the mean is good to 0.035 deg (one sigma).
  EXPECT_THAT(*result.roll, AngleNearDeg(kMounting.roll, 0.15));
  EXPECT_THAT(*result.pitch, AngleNearDeg(kMounting.pitch, 0.15));
  EXPECT_THAT(*result.yaw, AngleNearDeg(kMounting.yaw, 0.15));
}

// The motion estimator alone on a textured road, 1 m a frame: it takes a first look at every 5th
// frame without a guide, and the median of what those found guides every frame's search for the
// road (a camera yawed 3.5 deg). Its windows are tested on blocks of frames (6 of the 12 here),
// its failed pairs leave holes, and it calibrates to the road plane's accuracy.
// 30 frames down a textured road at 10 Hz, 1 m a frame, seen from `mounting`; `paint` (when
// given) draws on frame i.
CameraFrameSource road_drive(const EulerAngles& mounting, const core::CameraIntrinsics& intrinsics,
                             const std::function<void(cv::Mat&, int)>& paint = {}) {
  auto pictures = std::make_shared<std::vector<cv::Mat>>();
  CameraFrameSource frames;
  for (int i = 0; i < 30; ++i) {
    pictures->push_back(testing::road_picture(mounting, intrinsics, 1.0 * i));
    if (paint) paint(pictures->back(), i);
    frames.times.push_back(0.1 * i);
  }
  frames.read = [pictures](std::size_t index) { return (*pictures)[index]; };
  return frames;
}

// The motion estimator alone on road_drive's frames: windows of 12, a first look at every 5th.
CameraCalibrationOptions motion_on_road_drive() {
  CameraCalibrationOptions options = short_windows();
  options.method = CameraMethod::kMotion;
  options.motion_guide_frame_step = 5;
  options.motion_guide_min_frames = 4;
  return options;
}

// A car held at a steady acceleration (here from 6 to 20 m/s at 4 m/s^2) is steady through its
// windows, and its body pitches on the suspension for as long (docs/methods.md, camera §4). The
// windows of an estimator that reads no motion of its own (the geometric; here a caller's that
// gives the exact angles, on a textured road) are gated after the run by the road's motion in a
// few frame pairs of each (window_motion_check.hpp), refused and counted. Before, they were `ok`.
// At a steady speed the windows are kept, their motion known, and the note says the images gated
// accelerations; with the car's motion from a log they are not looked at.
TEST(CalibrateCamera, WindowsThroughASteadyAccelerationAreRefused) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const auto drive = [&intrinsics](double speed_mps, double acceleration_mps2) {
    auto pictures = std::make_shared<std::vector<cv::Mat>>();
    CameraFrameSource frames;
    for (int i = 0; i < 36; ++i) {
      const double time = 0.1 * i;
      pictures->push_back(testing::road_picture(
          kMounting, intrinsics, speed_mps * time + 0.5 * acceleration_mps2 * time * time));
      frames.times.push_back(time);
    }
    frames.read = [pictures](std::size_t index) { return (*pictures)[index]; };
    return frames;
  };
  CameraCalibrationOptions options = short_windows();
  options.estimator_name = "exact";
  options.estimator = [](const cv::Mat&, const core::CameraIntrinsics& camera) {
    return exact_estimate(kMounting, camera);
  };
  const CameraFrameSource speeding = drive(6.0, 4.0);
  const CalibrationResult speeding_up = calibrate_camera(speeding, intrinsics, options);
  EXPECT_EQ(speeding_up.status, CalibrationStatus::kInsufficientData);
  EXPECT_THAT(speeding_up.reason,
              ::testing::HasSubstr("refused 0 for turning (mean yaw rate above 0.5 deg/s) and 3 "
                                   "for speeding up or braking"));
  EXPECT_EQ(speeding_up.support.at("windows_refused_accelerating"), 3);
  EXPECT_EQ(speeding_up.support.at("window_motion_judged"), 3);
  EXPECT_FALSE(speeding_up.pitch.has_value());
  // The readings, a point per window: the speed's slope at the assumed height of 1.5 m, the
  // road's camera's.
  bool read = false;
  for (const Series& series : speeding_up.series) {
    if (series.name != "window_image_acceleration") continue;
    read = true;
    ASSERT_EQ(series.value.size(), 3U);
    for (const double acceleration : series.value) EXPECT_NEAR(acceleration, 4.0, 0.4);
  }
  EXPECT_TRUE(read);

  CameraCalibrationOptions not_gated = options;
  not_gated.gate_window_motion = false;
  EXPECT_TRUE(calibrate_camera(speeding, intrinsics, not_gated).ok());

  const CalibrationResult steady = calibrate_camera(drive(10.0, 0.0), intrinsics, options);
  ASSERT_TRUE(steady.ok()) << steady.reason;
  EXPECT_EQ(steady.support.at("windows"), 3);
  EXPECT_EQ(steady.support.at("window_motion_judged"), 3);
  EXPECT_THAT(steady.reason, ::testing::HasSubstr("the images' motion gated accelerations"));

  CameraFrameSource logged = speeding;
  logged.motion.assign(36, VehicleMotion{.speed_mps = 12.0});
  const CalibrationResult with_log = calibrate_camera(logged, intrinsics, options);
  ASSERT_TRUE(with_log.ok()) << with_log.reason;
  EXPECT_FALSE(with_log.support.contains("window_motion_checked"));
}

TEST(CalibrateCamera, MotionAloneGuidesItselfByAFirstLookAndCalibrates) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(0.8), rad_from_deg(1.5), rad_from_deg(3.5)};
  const CameraFrameSource frames = road_drive(mounting, intrinsics);
  CameraCalibrationOptions options = motion_on_road_drive();
  const CalibrationResult result = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_EQ(result.method, "motion");
  EXPECT_EQ(result.diagnostics.at("motion_first_look_frames"), 6.0);
  EXPECT_EQ(result.diagnostics.at("steadiness_block_frames"), 6.0);  // half the window of 12
  EXPECT_NEAR(result.diagnostics.at("motion_guide_yaw_deg"), 3.5, 0.15);
  EXPECT_NEAR(result.diagnostics.at("motion_guide_roll_deg"), 0.8, 0.15);
  EXPECT_GE(result.support.at("windows"), 2);
  EXPECT_THAT(*result.roll, AngleNearDeg(mounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(mounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(mounting.yaw, 0.1));

  options.motion_guide_frame_step = 0;
  EXPECT_EQ(calibrate_camera(frames, intrinsics, options).diagnostics.count("motion_guide_yaw_deg"),
            0U);
}

// A rear camera under the motion estimator: the car's travel points behind it, and the travel's
// line meets the image at the road's vanishing point all the same (it was no_road_plane in every
// frame, insufficient data); the facing check turns the yaw.
TEST(CalibrateCamera, MotionCalibratesACameraThatLooksBack) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(0.8), rad_from_deg(1.5),
                             wrap_angle(kPi + rad_from_deg(3.5))};
  const CalibrationResult result =
      calibrate_camera(road_drive(mounting, intrinsics), intrinsics, motion_on_road_drive());
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_THAT(*result.roll, AngleNearDeg(mounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(mounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(mounting.yaw, 0.1));
  EXPECT_THAT(result.reason, ::testing::HasSubstr("the camera looks back"));
  EXPECT_NEAR(std::abs(result.diagnostics.at("motion_guide_yaw_deg")), 180.0 - 3.5, 0.15);
}

// Frames through a lossy codec lose the asphalt's fine grain, and a small Lucas-Kanade window then
// follows the coding's noise; such a source is tracked with lossy_tracking_window_px (and says so).
TEST(CalibrateCamera, MotionTracksLossyFramesWithALargerWindow) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(0.8), rad_from_deg(1.5), rad_from_deg(3.5)};
  CameraFrameSource frames = road_drive(mounting, intrinsics, [](cv::Mat& picture, int) {
    std::vector<unsigned char> coded;
    cv::imencode(".jpg", picture, coded, {cv::IMWRITE_JPEG_QUALITY, 30});
    picture = cv::imdecode(coded, cv::IMREAD_UNCHANGED);
  });
  const CameraCalibrationOptions options = motion_on_road_drive();

  frames.lossy = true;
  const CalibrationResult lossy = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(lossy.ok()) << lossy.reason;
  EXPECT_EQ(lossy.diagnostics.at("motion_tracking_window_px"), 41.0);
  EXPECT_THAT(lossy.reason, ::testing::HasSubstr("lossy codec"));
  EXPECT_THAT(*lossy.roll, AngleNearDeg(mounting.roll, 0.1));
  EXPECT_THAT(*lossy.pitch, AngleNearDeg(mounting.pitch, 0.1));
  EXPECT_THAT(*lossy.yaw, AngleNearDeg(mounting.yaw, 0.1));

  // The same frames taken as lossless: the 21-px window's roll is 0.2 deg off.
  frames.lossy = false;
  const CalibrationResult as_lossless = calibrate_camera(frames, intrinsics, options);
  EXPECT_EQ(as_lossless.diagnostics.count("motion_tracking_window_px"), 0U);
  ASSERT_TRUE(as_lossless.roll.has_value());
  EXPECT_GT(std::abs(deg_from_rad(*as_lossless.roll - mounting.roll)), 0.15);
}

// A bonnet over the bottom 15 % of the image stays put while the road moves (lit brighter and
// darker as the car turns): its corners outvote the road's, the pairs fit the identity and end
// too_little_motion. The calibrator finds the bonnet first (car_region.hpp) and leaves it out; a
// given region does the same.
TEST(CalibrateCamera, MotionLeavesOutTheCarsOwnBonnet) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(0.8), rad_from_deg(1.5), rad_from_deg(3.5)};
  const cv::Mat bonnet = testing::bonnet_shape(cv::Size(intrinsics.width, intrinsics.height), 0.15);
  const CameraFrameSource frames =
      road_drive(mounting, intrinsics, [&bonnet](cv::Mat& picture, int i) {
        testing::paint_bonnet(picture, bonnet, 1.0 + 0.2 * std::sin(0.9 * i));
      });
  CameraCalibrationOptions options = motion_on_road_drive();

  options.detect_car_region = false;
  const CalibrationResult blind = calibrate_camera(frames, intrinsics, options);
  EXPECT_FALSE(blind.ok());
  EXPECT_GE(blind.rejections.at("too_little_motion"), 20);

  options.detect_car_region = true;
  const CalibrationResult found = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(found.ok()) << found.reason;
  // The bonnet's edge, highlight and grain with the margin around them; on this road, driven
  // without weaving, the solid line and the horizon it runs to are as still, and join them.
  EXPECT_GT(found.diagnostics.at("car_region_share"), 0.02);
  EXPECT_LT(found.diagnostics.at("car_region_share"), 0.35);
  EXPECT_THAT(found.reason, ::testing::HasSubstr("the car's own body"));
  EXPECT_THAT(*found.roll, AngleNearDeg(mounting.roll, 0.1));
  EXPECT_THAT(*found.pitch, AngleNearDeg(mounting.pitch, 0.1));
  EXPECT_THAT(*found.yaw, AngleNearDeg(mounting.yaw, 0.1));

  options.detect_car_region = false;
  options.ignored_region = bonnet;
  const CalibrationResult given = calibrate_camera(frames, intrinsics, options);
  ASSERT_TRUE(given.ok()) << given.reason;
  EXPECT_EQ(given.diagnostics.count("car_region_share"), 0U);
  EXPECT_NEAR(given.diagnostics.at("ignored_region_share"), mask_share(bonnet), 1e-12);
  EXPECT_THAT(*given.pitch, AngleNearDeg(mounting.pitch, 0.1));

  options.estimator = [](const cv::Mat&, const core::CameraIntrinsics&) { return FrameEstimate{}; };
  EXPECT_THROW(calibrate_camera(frames, intrinsics, options), std::invalid_argument);
  options.estimator = {};
  options.ignored_region = cv::Mat(10, 10, CV_8U, cv::Scalar(0));
  EXPECT_THROW(calibrate_camera(frames, intrinsics, options), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera
