// The camera's temporal filter (paper §III-A "Rotation Derivation" and §IV-A "Calibration
// result"; DESIGN §2, issue 14 item 4): per-frame angles are trusted only in stable stretches.
//
// The paper "continuously calculate[s] the standard deviation (Std) of a fixed number of VPs and
// angles. If the Std falls below a threshold, we consider as the car is driving on a straight road
// and the road is flat" (n = 100 frames, e = 0.005 rad, §IV-A) and outputs the average rotation
// (eq:camera_R3 - eq:camera_roll). Here:
//   - a stretch is a run of usable frames (the estimator gave angles; the car, when its motion is
//     known, fast enough and not turning) with no gap longer than max_gap_s; a gated or unusable
//     frame, or a gap, ends it (an unusable one may instead leave a hole: options);
//   - a window is the last window_frames usable frames of a stretch; it passes when the std of
//     each of roll, pitch and yaw over it is below max_window_std (for a noisy estimator: the std
//     of the means of blocks of its frames, options). A passing window is recorded and the
//     next one starts after it, so windows never share frames (the paper slides its window; the
//     disjoint windows here count each frame once and make the spread between windows an honest
//     measure of their error);
//   - without the car's motion, the images' (ImageMotion: the road plane's turn and travel between
//     frames, auto) gates whole windows: a steady window along a long curve or through an
//     acceleration is refused, and the window slides on;
//   - the estimate is the average of the passing windows' means, each weighted by
//     1 / (std^2 + weight_floor^2), its spread;
//   - its standard error comes from the spread between windows (core/standard_error.hpp: moving
//     blocks of block_s over the windows' times, the Student-t factor of their count), never below
//     the floor: biases no spread shows (the road's camber, the drive's mean heading in its lane,
//     the load's pitch). With one window, its frames' std stands in for the spread.
//   - a frame may also bring the road plane's angles (auto: the motion estimator's): the roll of
//     its horizon, free of the road's crossfall, and the pitch of the car's travel between the
//     two frames, free of the road's grade changing ahead of the car (which bends the lines that
//     make the vanishing point); each scatters by ~0.3 deg a frame, too much for the window's
//     test. The window is still judged on the steady angles; when at least
//     min_road_plane_frames of its frames bring them, its roll and pitch are their means (frames
//     beyond road_plane_clip median absolute deviations from the median in either left out) and
//     their spreads the means' standard errors (their std over the square root of half their
//     number: consecutive frame pairs share a frame).
// Incremental: feed frames in time order with add(), read current() at any time. A caller that
// looks at the images after the run may refuse windows the car stood through
// (refuse_standing_windows), or sped up, braked or turned through (gate_windows_by_image_motion).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::camera {

// The car's motion at a frame, when a GNSS/INS log or odometry gives it.
struct VehicleMotion {
  double speed_mps = 0.0;  // [m/s]
  double yaw_rate = 0.0;   // [rad/s]
  // Along the track: the change of the speed per second [m/s^2].
  double acceleration_mps2 = 0.0;
  // Backing up: the road's vanishing point is still ahead of the car, but the images' flow runs
  // into it, as a camera that looks back sees it (facing_check.hpp); gated.
  bool reversing = false;
};

// The car's motion between a frame and the one before, seen in the images (the road plane's
// homography, road_plane_motion.hpp): its yaw rate, and its speed in units of the camera's height
// above the road, which the images cannot tell apart from the height.
struct ImageMotion {
  double yaw_rate = 0.0;           // [rad/s], left positive
  double speed_over_height = 0.0;  // [1/s]
};

// What the road plane between a frame and the one before says about the car (auto;
// road_plane_motion.hpp).
struct RoadPlaneAngles {
  double roll = 0.0;   // with the road plane's horizon [rad]
  double pitch = 0.0;  // of the car's travel between the frames [rad]
  double yaw = 0.0;    // of the car's travel between the frames [rad]
  std::optional<ImageMotion> motion;
};

struct TemporalFilterOptions {
  // The paper's window: n = 100 frames (§IV-A).
  int window_frames = 100;
  // The paper's threshold e = 0.005 rad on the std of each angle over a window (§IV-A).
  double max_window_std = 0.005;  // [rad]
  // The window's test on the means of consecutive blocks of this many frames instead of on each
  // frame's angles (1: the paper's test). An estimator whose angles scatter from frame to frame
  // with no memory (the road plane between two frames: ~0.3 deg a frame; the learned network's:
  // ~0.5 deg) never passes the paper's test on a straight road, though its window's mean is
  // good to a few hundredths of a degree; the means of 10 frames (1 s at 10 Hz) scatter by a third
  // of that, and still show every change of the car's heading or body that lasts a second or more
  // (a turn, a curve, a braking), which is what the test is for. The oldest frames of a window
  // left over by the blocks are in none. At most half of window_frames.
  int steadiness_block_frames = 1;
  // Whether a frame the estimator gave no angles for ends the stretch (the paper's: its window is
  // n consecutive estimates). An estimator that fails at random frames (a pair whose tracks found
  // no road plane) says nothing about the road there; with false such a frame only leaves a hole,
  // and the stretch ends at a gap longer than max_gap_s (a stop, a turn the estimator cannot
  // follow).
  bool unusable_frame_ends_stretch = true;
  // A gap between frames longer than this ends a stretch [s] (10 dropped frames at 10 Hz).
  double max_gap_s = 1.0;
  // Motion gate, applied only to frames that come with a VehicleMotion: slower than this the road
  // ahead says little about the car's axis (parking, queues) [m/s] ...
  double min_speed_mps = 3.0;
  // ... and while turning the road's direction is not the car's, and the body rolls [rad/s]
  // (1 deg/s: a 1 km radius at 60 km/h).
  double max_yaw_rate = rad_from_deg(1.0);
  // ... and while speeding up or braking the body pitches on its suspension (some 0.3-0.5 deg per
  // m/s^2), so the car's x axis leaves the road's lines: a steady acceleration out of a junction
  // or onto a highway is a steady window with a biased pitch [m/s^2].
  double max_acceleration_mps2 = 0.3;
  // Without a VehicleMotion the images tell the car's motion (ImageMotion, auto), and a steady
  // window is refused when the car turned or sped up through it: windows through a steady
  // acceleration or along a long curve are steady, and biased. The images' yaw rates and speeds
  // are too noisy frame by frame for the gate above, so it reads whole windows:
  //   - the mean of the frames' yaw rates above this [rad/s]: along a steady curve the lines'
  //     vanishing point, some way ahead, leads the car's heading by the yaw rate times the time
  //     the lines reach ahead (0.4-0.8 s on rendered highways: 0.5 deg of yaw at 0.8 deg/s), and
  //     the body rolls outward. The per-frame gate above (a GNSS/INS motion) allows twice this;
  //     a window's mean is sharp enough to be held tighter. A window that mixes straight road
  //     with part of a bend is left to the steadiness test and the windows' agreement;
  double max_window_yaw_rate = rad_from_deg(0.5);
  //   - the slope of the frames' speeds over height, times this height, above
  //     max_acceleration_mps2. The images measure the speed in units of the camera's height above
  //     the road; this turns it into m/s^2 [m]: a windscreen camera of a passenger car sits at
  //     1.2-1.6 m, and a taller mounting (a truck's at 2.5 m) gates less than it should by the
  //     ratio of the heights.
  double image_motion_camera_height_m = 1.5;
  //   - either only when it lies more than this many of its standard errors from 0 (from the
  //     yaw rates' spread over the square root of their count; from the speeds' residuals about
  //     their line): a refusal needs evidence. The auto run's windows read ~100 pairs and are
  //     sharp; the window motion check (window_motion_check.hpp) reads a dozen, and where most
  //     of them found no road plane (a 30 Hz street of 1.2-s windows in the tests: 6 pairs),
  //     their noise alone read 0.9 deg/s of yaw rate on a straight road.
  double image_motion_significance = 3.0;
  // Added to each window's std in its weight, so that one window with an accidentally tiny spread
  // does not outweigh the rest [rad].
  double weight_floor = 0.001;
  // Windows closer in time than this share the same road and light; the standard error treats
  // them as one block [s] (core/standard_error.hpp).
  double block_s = 30.0;
  // The floor of the standard errors [rad], added in quadrature: the road's crossfall tilts the
  // horizon of gravity against the car's (up to ~1 deg on a cambered road, mostly one way in one
  // driving direction); a driver holds the lane's direction to ~0.05 deg on average; load and
  // grade move the pitch by a few hundredths of a degree.
  EulerAngles standard_error_floor{rad_from_deg(0.1), rad_from_deg(0.05), rad_from_deg(0.05)};
  // A window's roll and pitch are the road plane's when at least this many of its frames bring
  // them (a third of the paper's window: the mean of 33 frames scattered by 0.3 deg is good to
  // ~0.07 deg).
  int min_road_plane_frames = 33;
  // Frames whose road-plane roll or pitch lies farther than this many (scaled) median absolute
  // deviations from the window's median are left out of its means: a pair whose tracks locked
  // onto a passing car or a shadow.
  double road_plane_clip = 3.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// What add() did with a frame.
enum class FrameVerdict {
  kBuffered,      // usable; in the current window
  kWindowPassed,  // usable, and it completed a passing window
  kNoEstimate,    // the estimator gave no angles; the stretch ends
  kSlow,          // gated: slower than min_speed_mps; the stretch ends
  kTurning,       // gated: |yaw rate| above max_yaw_rate; the stretch ends
  kAccelerating,  // gated: |acceleration| above max_acceleration_mps2; the stretch ends
  kReversing,     // gated: the car backs up (VehicleMotion::reversing); the stretch ends
};
const char* to_string(FrameVerdict verdict);  // "buffered", "window_passed", "no_estimate", ...

// The motion gate alone: kSlow, kReversing, kTurning or kAccelerating when `motion` fails it,
// nothing when it passes or is unknown. add() applies it first, so a caller may skip estimating the
// frames it gates.
std::optional<FrameVerdict> motion_gate(const std::optional<VehicleMotion>& motion,
                                        const TemporalFilterOptions& options);

// What the image motion gate reads of one window's frame pairs, and its verdict.
struct ImageMotionJudgement {
  double yaw_rate = 0.0;           // the mean of the pairs' yaw rates [rad/s], left positive
  double acceleration_mps2 = 0.0;  // the slope of their speeds over height, times the height
  // Their standard errors (infinite with too few pairs: 2 for the yaw rate, 3 for the slope).
  double yaw_rate_error = 0.0;
  double acceleration_error_mps2 = 0.0;
  // kTurning or kAccelerating when the window fails the gate.
  std::optional<FrameVerdict> refused;
};

// The image motion gate's test on one window's frame pairs (ImageMotion; `times` [s] of the pairs,
// from any origin; non-finite ones left out; pairs beyond road_plane_clip MADs of the yaw rates, or
// of the speeds about their line, left out too: tracks that locked onto a passing car): kTurning
// when the mean of the yaw rates exceeds max_window_yaw_rate, kAccelerating when the slope of the
// speeds over height, times image_motion_camera_height_m, exceeds max_acceleration_mps2; either
// only beyond image_motion_significance standard errors. TemporalFilter applies it to the frames of
// each steady window that bring an ImageMotion (auto); window_motion_check.hpp to a few pairs of
// the windows of an estimator that reads none. Throws std::invalid_argument unless there is one
// time per motion.
ImageMotionJudgement judge_image_motion(const std::vector<double>& times,
                                        const std::vector<ImageMotion>& motions,
                                        const TemporalFilterOptions& options);

// One passing window.
struct FilterWindow {
  std::size_t first_frame = 0;  // indices of add() calls, from 0
  std::size_t last_frame = 0;
  double start_time = 0.0;  // [s]
  double end_time = 0.0;
  EulerAngles mean;  // [rad]
  // Of the frames in it (of its blocks' means with steadiness_block_frames) [rad]; the road
  // plane's roll and pitch: their means' standard errors.
  EulerAngles std;
  // The frames whose road-plane angles made the window's roll and pitch (0: they are the steady
  // angles').
  std::size_t road_plane_frames = 0;
  // Whether the car's motion through the window was known, from a VehicleMotion of every frame or
  // from the images (ImageMotion): only then were accelerations and curves gated.
  bool motion_known = false;
  // Whether every frame of the window came with a VehicleMotion (`--ins`): only then were the
  // accelerations that pitch the body measured rather than read from the images.
  bool vehicle_motion_known = false;
};

struct FilterEstimate {
  bool ok = false;             // at least one window passed
  EulerAngles angles;          // [rad], when ok
  EulerAngles standard_error;  // [rad], when ok
  std::size_t windows = 0;
  std::size_t frames_in_windows = 0;
  std::size_t road_plane_windows = 0;  // windows whose roll and pitch are the road plane's
  std::size_t road_plane_frames = 0;   // the frames behind them
  // Windows whose car motion was known (FilterWindow::motion_known).
  std::size_t motion_known_windows = 0;
  // Windows whose every frame had a VehicleMotion (FilterWindow::vehicle_motion_known).
  std::size_t vehicle_motion_windows = 0;
  // The share of the pitch's weighted mean that the windows without it carry, in [0, 1].
  double pitch_weight_without_vehicle_motion = 0.0;
  // Times a steady window was refused by the image motion gate: turning, accelerating (a window
  // slides on by a frame after a refusal, so one curve counts many times; a window refused after
  // the fact, gate_windows_by_image_motion, counts once).
  std::size_t windows_refused_turning = 0;
  std::size_t windows_refused_accelerating = 0;
  // Windows refused after the fact because the car stood through them (refuse_standing_windows).
  std::size_t windows_refused_standing = 0;
  // Why not ok: "only 43 frames in stable stretches; need 100", or the smallest std reached.
  std::string reason;
};

class TemporalFilter {
 public:
  // Throws std::invalid_argument when the options fail Check().
  explicit TemporalFilter(TemporalFilterOptions options = {});

  // One frame, in time order (a time not after the previous one throws std::invalid_argument):
  // its angles when the estimator gave them, its motion when known, and the road plane's angles
  // when the frame has them (averaged, not tested for steadiness: see above). The
  // motion gate comes first: a gated frame is kSlow or kTurning whether or not it has angles.
  FrameVerdict add(double time_s, const std::optional<EulerAngles>& angles,
                   const std::optional<VehicleMotion>& motion = std::nullopt,
                   std::optional<RoadPlaneAngles> road_plane = std::nullopt);

  // Refuses passed windows after the fact: stood[k] is whether the car stood through windows()[k]
  // (the images did not move: standing_check.hpp). Such a window is steady without the car
  // driving, and one view repeated has the smallest spread, so the largest weight, of all: it
  // says nothing of straight driving. They leave windows() and are counted in current().
  // Throws std::invalid_argument unless there is one flag per window.
  void refuse_standing_windows(const std::vector<bool>& stood);

  // The image motion gate after the fact, for an estimator whose frames bring no ImageMotion (the
  // geometric: window_motion_check.hpp): judgements[k] for windows()[k], nullopt where the images
  // could not tell. A refused window leaves windows() and is counted as turning or accelerating in
  // current(); a kept one that was judged is marked motion_known. Throws std::invalid_argument
  // unless there is one per window.
  void gate_windows_by_image_motion(
      const std::vector<std::optional<ImageMotionJudgement>>& judgements);

  // The estimate from the windows so far.
  FilterEstimate current() const;

  const std::vector<FilterWindow>& windows() const { return windows_; }
  std::size_t frames() const { return frames_; }
  // Frames that were usable (estimated and not gated), and the longest stretch of them.
  std::size_t usable_frames() const { return usable_frames_; }
  std::size_t longest_stretch() const { return longest_stretch_; }

 private:
  struct Buffered {
    std::size_t frame;
    double time;
    EulerAngles angles;
    bool has_vehicle_motion;
    std::optional<RoadPlaneAngles> road_plane;
  };
  void end_stretch();
  bool window_passes(EulerAngles& mean, EulerAngles& std) const;
  // The image motion gate on the current window: kTurning or kAccelerating when it fails, nothing
  // when it passes; `known` tells whether the car's motion through it was known at all.
  std::optional<FrameVerdict> image_motion_gate(bool& known) const;
  void take_road_plane_angles(FilterWindow& window) const;

  TemporalFilterOptions options_;
  std::vector<Buffered> window_;  // the current window, oldest first (at most window_frames)
  std::vector<FilterWindow> windows_;
  std::size_t frames_ = 0;
  std::size_t usable_frames_ = 0;
  std::size_t stretch_ = 0;
  std::size_t longest_stretch_ = 0;
  std::optional<double> last_time_;
  std::optional<double> last_usable_time_;
  // The smallest largest-of-three std of any full window that did not pass [rad], for the reason.
  std::optional<EulerAngles> steadiest_failed_;
  std::size_t refused_turning_ = 0;
  std::size_t refused_accelerating_ = 0;
  std::size_t refused_standing_ = 0;
};

}  // namespace x2car::camera
