// Camera -> car: roll, pitch and yaw from the vanishing point of the road and the horizon, frame by
// frame, kept where they are steady (DESIGN §2, paper §III-A; issue 14).
//
// One pass over the frames: they are decoded and estimated in parallel (a oneTBB pipeline; the
// motion gate is applied before decoding, so gated frames cost nothing), and fed in time order to
// the temporal filter (temporal_filter.hpp). Each frame's vanishing point and horizon become the
// mounting's angles exactly (vanishing_rotation.hpp). The result is the filter's average over its
// passing windows with their standard errors; too few steady frames is insufficient_data with the
// filter's reason, windows that disagree with each other beyond max_window_disagreement is
// unreliable.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/car_region.hpp"
#include "x2car/camera/facing_check.hpp"
#include "x2car/camera/frame_estimate.hpp"
#include "x2car/camera/geometric_estimator.hpp"
#include "x2car/camera/road_plane_motion.hpp"
#include "x2car/camera/standing_check.hpp"
#include "x2car/camera/temporal_filter.hpp"
#include "x2car/camera/window_motion_check.hpp"
#include "x2car/core/calibration_result.hpp"
#include "x2car/core/camera_model.hpp"
#include "x2car/core/enum_names.hpp"

namespace x2car::camera {

// Which per-frame estimates the calibrator makes (issue 14 item 2; docs/methods.md, camera §1-1a).
// Which way the camera looks along the car (CameraCalibrationOptions::facing).
enum class CameraFacing { kFromMotion, kAhead, kBack };

constexpr std::array<EnumName<CameraFacing>, 3> kCameraFacingNames{{
    {CameraFacing::kFromMotion, "auto"},
    {CameraFacing::kAhead, "ahead"},
    {CameraFacing::kBack, "back"},
}};

enum class CameraMethod {
  kGeometric,  // "geometric": the lines' vanishing point and the vertical vanishing point's
               //   (gravity's) horizon, from each image alone
  kMotion,     // "motion": the car's travel (pitch, yaw) and the road plane (roll) from each frame
               //   and the one before it (road_plane_motion.hpp)
  kAuto,       // "auto": the lines' angles decide which windows are steady and give the yaw (the
               //   more precise); roll and pitch are the road plane's (the road's horizon, not
               //   gravity's, and the car's travel, not the lines' far ahead, from its motion),
               //   averaged over each window (temporal_filter.hpp)
};

constexpr std::array<EnumName<CameraMethod>, 3> kCameraMethodNames{{
    {CameraMethod::kGeometric, "geometric"},
    {CameraMethod::kMotion, "motion"},
    {CameraMethod::kAuto, "auto"},
}};

inline const char* to_string(CameraMethod method) {
  return enum_to_string(kCameraMethodNames, method);
}

struct CameraCalibrationOptions {
  CameraMethod method = CameraMethod::kGeometric;
  // A single-image estimator that replaces `method` (a learned one, a test's); empty: `method`.
  FrameEstimator estimator;
  // The name the result's `method` reports for `estimator`.
  std::string estimator_name;
  // Whether `estimator`'s angles scatter from frame to frame (a learned one): it is then filtered
  // as the motion estimator is (noisy_estimator_block_frames).
  bool estimator_scatters = false;
  // `estimator` calibrates only from at least this many steady windows. A learned one's error
  // follows the scene for seconds (docs/methods.md, camera §1b), which a window's own spread does
  // not show and the spread between windows (max_window_disagreement) does: on the one-minute KITTI
  // drive mixed 303 the shipped network's only window said yaw 2.8 deg off the truth at a standard
  // error of 0.28 deg. Fewer is insufficient_data.
  int estimator_min_windows = 2;
  // Added in quadrature to the standard errors of `estimator`'s angles, each its own [rad]: its own
  // error on a drive, which its windows share and no spread between them shows (0: none; a learned
  // estimator's: camera_net::LearnedEstimatorOptions::standard_error_floor).
  EulerAngles estimator_standard_error_floor;
  GeometricEstimatorOptions geometric;
  RoadPlaneMotionOptions motion;
  // For frames that came through a lossy codec (CameraFrameSource::lossy: JPEG, video), the motion
  // estimator's Lucas-Kanade window [px] and its corners' spacing [px] in place of motion's
  // tracking_window_px and min_feature_distance_px. Such a codec removes the asphalt's fine grain,
  // and a 21-px window then follows the coding's noise: on rendered drives as H.264 at 0.18 bits a
  // pixel, the road plane's roll scattered 7 times as much frame to frame as from the lossless
  // images (tracks 0.77 px off instead of 0.26) and no window was steady. A 41-px window sees the
  // coarser texture that survives; corners 12 px apart keep their windows from repeating each other
  // (and the work per frame below the lossless setting's). Lossless frames keep motion's own: with
  // fewer corners some sparse highway minutes ran out of tracks (docs/methods.md, camera §1a).
  int lossy_tracking_window_px = 41;
  double lossy_min_feature_distance_px = 12.0;
  // Pixels the geometric and motion estimators leave out (8-bit, the intrinsics' size; nonzero:
  // left out): the car's own body in view, a logo burnt into the video. Given, it replaces
  // detect_car_region; it overrides geometric's and motion's own. Empty: none given.
  cv::Mat ignored_region;
  // Without ignored_region, for motion and auto: first look for the car's own body in the images
  // (car_region.hpp: texture that stays in place while the scene moves) and leave it out of the
  // road plane. Not the geometric estimator's (a solid lane line on a straight road can be as
  // still, and its segments are wanted) nor a caller's `estimator`, which sees whole images.
  bool detect_car_region = true;
  CarRegionOptions car_region;
  // motion: before the run, every this many frames a first look at the road plane without a guide;
  // when at least motion_guide_min_frames of them give one, the median of their angles guides
  // every frame's search for the road (RoadPlaneMotionOptions::max_seed_travel_over_height) in
  // place of a level camera looking ahead: at highway speed a camera yawed 4 deg sends that
  // search down the wrong direction, and most pairs find no road. 0: no first look. 10 costs a
  // tenth more time.
  int motion_guide_frame_step = 10;
  int motion_guide_min_frames = 10;
  // The frames the first look decodes (a fifth of them at step 10, with tracked_frames 2) are kept
  // for the run, up to this many bytes of images [B], and let go once the run has passed them:
  // decoding is a sixth of the motion estimator's time. 0: none kept (the run decodes them again).
  std::size_t first_look_kept_bytes = std::size_t{256} << 20;
  // Estimate at most this many frames a second, 10 % over it allowed: every n-th frame
  // (frames_apart_for_rate: a 30 Hz video at 10, every 3rd; 12 Hz, every 2nd) [Hz]. The others
  // are not estimated, nor read (a video still decodes each in turn), and the run goes on at the
  // kept frames' rate (options_at_frame_rate; a window_frames_at_any_rate counts kept frames).
  // The paper's camera ran at 10 Hz; a faster one calibrates in proportion to its frames: on a
  // simulated 30 Hz minute (mixed 304, geometric) every frame gave the result of every 3rd within
  // 0.003 deg at three times the time (docs/methods.md, camera §3). Kept frames must stay close
  // enough for the run's pairs (max_pair_gap_s for motion and auto, facing_pair_max_gap_s,
  // standing_check.pair_max_gap_s): calibrate_camera refuses a rate that parts them further.
  // 0: every frame.
  double max_frame_rate_hz = 0.0;
  // The motion estimator's frames are this many frames apart (given at filter_frame_rate_hz, and
  // scaled with the frames' rate as the counts below are): it pairs each frame with the one
  // motion_frame_step frames before it. 1 at 10 Hz: pairs 0.1 s apart, KITTI's camera's. At 30 Hz
  // the frame before is a third of the travel away, and the road's parallax, from which the plane
  // comes, a third of it: on a simulated 30 Hz mixed drive 16 % of the pairs were
  // too_little_motion where its 10 Hz twin had 7.5 %. Scaled to 3 there, a pair spans 0.1 s again.
  int motion_frame_step = 1;
  // The motion estimator pairs a frame with one before it when they are at most this far apart
  // [s] (frames dropped between them stretch the step); otherwise the frame is no_previous_frame
  // (0.25 s: down to 4 Hz video; past it the road ahead moves out of the lower image between
  // frames at city speeds).
  double max_pair_gap_s = 0.25;
  // The paper's window and threshold, the motion gate, the averaging and the standard errors.
  // Its frame counts (window_frames, min_road_plane_frames) and noisy_estimator_block_frames below
  // are given at filter_frame_rate_hz; its steadiness_block_frames holds at any rate.
  TemporalFilterOptions filter;
  // The frame rate the frame counts above are given at [Hz]: the paper's n = 100 frames are 10 s of
  // KITTI's 10 Hz camera (§IV-A). Frames at another rate (one over the mean interval of the
  // frames' times, of those within half and twice the median one) get windows of as many seconds,
  // the counts scaled by the ratio of the rates: a 30 Hz video's windows hold 300 frames, a 5 Hz
  // log's 50. The steadiness test asks for as long a straight, even stretch of road at any rate;
  // a 30 Hz video windowed by 100 frames passed windows of 3.3 s through curves and
  // accelerations (simulated mixed drive 304 at 30 Hz: nine windows that disagreed by 0.9 deg in
  // pitch, where its 10 Hz twin had one steady window). The first look's motion_guide_frame_step
  // and motion_frame_step are scaled alike (a sample a second; pairs 0.1 s apart). 0: the counts as
  // given, at any rate.
  double filter_frame_rate_hz = 10.0;
  // Rates within this share of filter_frame_rate_hz keep the counts as given: KITTI's camera,
  // the paper's, runs at 9.65 Hz by its timestamps (0.1036 s), and its n is 100.
  double filter_frame_rate_tolerance = 0.1;
  // A window of exactly this many frames at any rate (the CLI's --window-frames) in place of the
  // scaled filter.window_frames; the other counts still follow the rate.
  std::optional<int> window_frames_at_any_rate;
  // For an estimator whose angles scatter from frame to frame with no memory (motion: one pair's
  // road plane; `estimator_scatters`), the filter's steadiness_block_frames (at most half the
  // window), and a frame it gives no angles for leaves a hole in the stretch instead of ending it
  // (TemporalFilterOptions::unusable_frame_ends_stretch): the paper's test on each frame's angles
  // never passes for them. 10 frames: 1 s at 10 Hz, shorter than any turn or braking.
  int noisy_estimator_block_frames = 10;
  // The passing windows' means may differ by at most this much in any angle [rad] (largest minus
  // smallest); beyond it the result is unreliable: a steady but wrong stretch (a long curve of
  // constant radius, a road that leans one way) got through the filter.
  double max_window_disagreement = 0.01;
  // Added in quadrature to the roll's standard error when the roll is gravity's horizon (the
  // geometric estimator's, from the vertical vanishing point): the car sits on the road, whose
  // cross slope tilts it against gravity, and a drive's windows share one side of the road. Road
  // design puts that slope at 1.5-2.5 % on straight roads (0.9-1.4 deg, one way per driving
  // direction); 0.6 deg as one standard error covers it at two [rad]. The road plane's horizon
  // (motion; auto when every steady window has enough frames with one) does not carry it.
  double gravity_horizon_roll_floor = rad_from_deg(0.6);
  // Added in quadrature to the pitch's standard error when the car's motion is unknown (no
  // CameraFrameSource::motion, `--ins`): a car that speeds up or brakes pitches on its suspension
  // (passenger cars: 1-2 deg per g of longitudinal acceleration), and a window held through a
  // steady acceleration is steady, so it passes with that pitch and no spread shows it. 0.15 deg is
  // 1 m/s^2 (0.1 g) held through a window at 1.5 deg per g [rad]. With the motion known those
  // frames are gated (`accelerating`) and it is not added. Under auto the images' motion gates
  // whole windows (TemporalFilterOptions::max_window_yaw_rate), but it reads the acceleration at
  // an assumed camera height, and it is still added. With the motion of only some frames (an
  // `--ins` log over part of the drive), it is scaled by the share of the pitch's weighted mean
  // that the windows without it carry.
  double unknown_motion_pitch_floor = rad_from_deg(0.15);
  // Whether the camera looks ahead or back: the vanishing point of the road (and the motion
  // estimator's line of travel) gives the car's x axis only up to its sign.
  // kFromMotion: from the images' motion (facing_check.hpp): a camera found looking back has its
  // yaw turned by 180 deg and the note says so; moving frame pairs that disagree make the result
  // unreliable; too few moving pairs leave it taken as looking ahead, said in the note. kAhead,
  // kBack: given (`--facing`), not checked.
  CameraFacing facing = CameraFacing::kFromMotion;
  FacingCheckOptions facing_check;
  // The facing check pairs each frame of a steady window with the first one of the window at
  // least facing_pair_interval_s later (at 30 Hz and walking pace the next frame's motion is
  // within the camera's own jitter), if that is at most facing_pair_max_gap_s later [s].
  double facing_pair_interval_s = 0.2;
  double facing_pair_max_gap_s = 0.5;
  // Whether a steady window the images show the car standing through is refused
  // (standing_check.hpp: a car at a light passes the window's steadiness test without driving, its
  // repeated view takes the largest weight of all, and it may wait at an angle to its lane).
  // Windows whose every frame had the car's motion (`--ins`) are not looked at: its speed gated
  // standing frames.
  bool refuse_standing = true;
  StandingCheckOptions standing_check;
  // Whether the steady windows of an estimator that reads no motion of its own (the geometric,
  // a caller's) are gated by the images' motion after the run (window_motion_check.hpp: a few of
  // each window's frame pairs through the motion estimator, judged by the filter's image motion
  // gate): a window through a steady acceleration (a start from standstill) or along a long curve
  // is steady and biased. Windows whose every frame had the car's motion (`--ins`) are not looked
  // at; nor are auto's and motion's, which read every pair's.
  bool gate_window_motion = true;
  WindowMotionCheckOptions window_motion_check;
  // A frame whose `read` throws InputError (a truncated or corrupt image) is skipped and counted
  // (rejections["unreadable_image"], the first message in `reason`). Off: the InputError ends the
  // run. An image whose size is not the intrinsics' always ends it (the wrong intrinsics).
  bool skip_bad_images = false;
  bool keep_series = true;  // per-frame vanishing points, horizons, angles and window flags
  // Called after each frame has passed the filter (in order, one thread at a time) with the frames
  // done and the total; empty: not called. Must not throw.
  std::function<void(std::size_t done, std::size_t total)> progress;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The frames of a drive: their times and how to decode each.
struct CameraFrameSource {
  std::vector<double> times;  // [s], strictly increasing
  // Decodes frame `index` (8-bit grey or BGR). Called from several threads at once, each index
  // once; throws InputError for an image it cannot decode.
  std::function<cv::Mat(std::size_t index)> read;
  // The frame's name in messages (its file); empty: "frame <index>".
  std::function<std::string(std::size_t index)> name;
  // The car's motion at each frame, when known (a GNSS/INS log); empty or one per frame.
  std::vector<std::optional<VehicleMotion>> motion;
  // Whether the frames came through a lossy codec (JPEG files or messages, a video): the motion
  // estimator then tracks with CameraCalibrationOptions::lossy_tracking_window_px.
  bool lossy = false;
};

// The frames calibrate_camera estimates at once: 2 per hardware thread, at least 4 and at most 64
// (each holds a decoded image, 25 MB at 4K in colour: on a 128-thread server 256 of them and the
// video decoder's 528 grey ones would be over 10 GB; capped, 64 and 144, about 2.8 GB, for no
// speed lost that a sequential decoder could feed).
// A source that decodes in order (a video) keeps about twice that many behind its decoder.
std::size_t camera_frames_in_flight();

// The frames' rate [Hz]: one over the mean interval between consecutive frames at `times` [s], of
// the intervals within half and twice the median one (a dropped frame, a stop in the recording, a
// repeated time left out); nullopt with no interval above zero.
std::optional<double> frames_rate_hz(const std::vector<double>& times);

// How many frames apart calibrate_camera estimates the frames at `times` [s] for
// CameraCalibrationOptions::max_frame_rate_hz: the frames' rate over it (10 % over it allowed),
// rounded up (30 Hz at 10: 3; 33 Hz: 3; 12 Hz: 2); 1 when it is 0 or the rate is unknown.
std::size_t frames_apart_for_rate(const std::vector<double>& times, double max_frame_rate_hz);

// `options` for frames at `times` (CameraCalibrationOptions::filter_frame_rate_hz): the counts of
// frames given at that rate (the filter's window_frames and min_road_plane_frames,
// noisy_estimator_block_frames, motion_guide_frame_step, motion_frame_step) hold as many seconds
// at the frames' own rate, one over the mean interval of `times` within half and twice the median
// one (a 30 Hz video: windows of 300 frames); a window never below 2 frames, a block or a step
// below 1; the filter's own steadiness_block_frames (1: the paper's test on each frame) kept, at
// most half the window. As given when filter_frame_rate_hz is 0, the rate is within
// filter_frame_rate_tolerance of it, or `times` has no interval; window_frames_at_any_rate, when
// set, is the window. calibrate_camera applies it.
CameraCalibrationOptions options_at_frame_rate(const CameraCalibrationOptions& options,
                                               const std::vector<double>& times);

// Returns ok, insufficient_data (the filter's reason: "only 43 frames in stable stretches; need
// 100") or unreliable; never NaN angles. InputError from `read` passes through unless
// skip_bad_images, and an image of the wrong size is an InputError naming the frame and its size;
// std::invalid_argument for invalid options or a source whose times or motion do not fit.
CalibrationResult calibrate_camera(const CameraFrameSource& frames,
                                   const core::CameraIntrinsics& intrinsics,
                                   const CameraCalibrationOptions& options = {});

}  // namespace x2car::camera
