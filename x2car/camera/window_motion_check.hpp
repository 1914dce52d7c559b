// Whether the car sped up, braked or turned through a steady window, read from the road's motion in
// a few of the window's frame pairs: the temporal filter's image motion gate (temporal_filter.hpp)
// for an estimator whose frames bring no motion of their own (the geometric, the learned).
//
// A steady window is the paper's sign of straight driving on flat road (§IV-A), but a car held at
// a steady acceleration through it is steady too: its body pitches on the suspension (passenger
// cars 1-2 deg per g) for as long as the acceleration lasts, and that pitch is in the lines'
// vanishing point. Most drives start from standstill, and a window over the start is steady:
// highway 9107 of the camera sweep (docs/methods.md, camera §4) came back `ok` with its pitch
// 1.07 deg off at a standard error of 0.20 deg from its one window, the start from 0 to 20 m/s.
// With
// `--ins` such frames are gated by the log, and `auto` reads the motion of every frame pair;
// without either, this looks at `pairs_per_window` pairs spread over each window, each through the
// motion estimator (road_plane_motion.hpp: the road plane's homography gives the camera's turn
// about the road's normal and its travel over its height), and judges their yaw rates and speeds
// over height as the filter judges auto's (judge_image_motion).
#pragma once

#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "x2car/camera/frame_estimate.hpp"
#include "x2car/camera/temporal_filter.hpp"
#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

struct WindowMotionCheckOptions {
  // Frame pairs looked at per window, evenly over it. The slope of 12 speeds spread over a 10-s
  // window, each good to ~2 % at highway speed, is good to ~0.03 m/s^2 at a height of 1.5 m, a
  // tenth of the gate's 0.3 m/s^2; each costs one motion estimate (~1/30 s on a core).
  int pairs_per_window = 12;
  // Fewer pairs that gave the car's motion (the others: too little motion, too few tracks, no road
  // plane) and the window is not judged: it stays, its motion unknown.
  int min_pairs = 6;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// A window to look at: its first and last frame (indices into the frames' times, inclusive) and,
// when known, where its vanishing point and horizon lie (the window's mean angles), which aims the
// motion estimator's search for the travel at highway speed.
struct MotionCheckWindow {
  std::size_t first_frame = 0;
  std::size_t last_frame = 0;
  std::optional<SequenceGuide> guide;
};

// What the pairs of one window showed.
struct WindowMotionCheck {
  std::size_t pairs = 0;  // looked at
  // Of the pairs that gave the car's motion: the later frame's time from the window's first [s],
  // and the motion.
  std::vector<double> times;
  std::vector<ImageMotion> motions;
  // When at least min_pairs gave the motion.
  std::optional<ImageMotionJudgement> judgement;
};

// The car's motion over a frame pair, from the camera's over it (the motion estimator's) and the
// pair's span [s]: its yaw rate and its speed over the camera's height.
inline ImageMotion image_motion_over(const CameraPairMotion& pair, double pair_s) {
  return ImageMotion{.yaw_rate = pair.turn_about_up / pair_s,
                     .speed_over_height = pair.travel_over_height / pair_s};
}

// One check per window. A pair is `sequence_frames` frames (the motion estimator's tracked frames,
// oldest first), `frame_step` apart, none more than `max_pair_gap_s` after the one before; pairs
// that would cross a larger gap or leave the window are not taken. `read(i)` gives frame i (empty:
// unreadable, the pair tells nothing), called in increasing order of i within each window and
// from one thread; `estimator` is called from several. The judgement is judge_image_motion's with
// `filter`'s thresholds.
std::vector<WindowMotionCheck> check_window_motion(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<MotionCheckWindow>& windows, std::size_t sequence_frames,
    std::size_t frame_step, double max_pair_gap_s, const SequenceEstimator& estimator,
    const core::CameraIntrinsics& intrinsics, const TemporalFilterOptions& filter,
    const WindowMotionCheckOptions& options = {});

}  // namespace x2car::camera
