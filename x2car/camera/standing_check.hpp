// Whether the car stood through a steady window, from the images' motion.
//
// The temporal filter takes a window whose per-frame angles hardly change for the car driving
// straight on a flat road (paper §IV-A: "If the Std falls below a threshold, we consider as the
// car is driving on a straight road"). A car standing at a light or in a queue passes that test
// without driving at all: its frames repeat one view (the same angles, a std near 0, so the
// window's weight in the average is the largest there is), and that view may be of a car waiting
// at an angle to its lane at a junction. With the car's motion known (`--ins`) such frames are
// gated by speed; without it, the images tell: corners of frames about half a second apart are
// tracked (pyramidal LK, both ways), and a pair whose corners stayed put (all but a few: people
// and cars pass a standing car) stood. A window where more of its tracked pairs stood than moved
// is the car's standing, not its driving.
#pragma once

#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

namespace x2car::camera {

struct StandingCheckOptions {
  // Pairs of frames looked at per window, evenly over it.
  int pairs_per_window = 4;
  // Each frame is paired with the first one at least pair_interval_s later (at 3 m/s half a
  // second moves a corner on the road 10 m ahead of a camera 1.5 m up by some 10 px at 1242 px
  // wide, a standing car's not at all), if that is at most pair_max_gap_s later [s].
  double pair_interval_s = 0.5;
  double pair_max_gap_s = 1.0;
  // Corners tracked per pair (cv::goodFeaturesToTrack).
  int corners_per_pair = 200;
  // A corner moved when it moved at least this far [px]: above the camera's jitter on an idling
  // engine and the tracker's noise (~0.05 px), below what a car creeping at 1 m/s moves the near
  // scene by in half a second.
  double min_corner_motion_px = 0.5;
  // A pair moved when at least this share of its tracked corners moved: a highway's distant trees
  // and hills hardly move in half a second, but the road, its markings and the near verges do; a
  // standing car sees a few people and cars pass.
  double min_moving_corner_share = 0.2;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// What the pairs of one window showed.
struct WindowMotionCheck {
  std::size_t pairs = 0;        // looked at
  std::size_t pairs_stood = 0;  // whose corners stayed put
  std::size_t pairs_moved = 0;  // tracked, and moved (the rest: too few corners to tell)
  bool stood() const { return pairs_stood > pairs_moved; }
};

// Whether a pair of frames moved: nullopt when fewer than 8 corners were tracked (a scene without
// texture: nothing to tell).
std::optional<bool> pair_moved(const cv::Mat& earlier, const cv::Mat& later,
                               const cv::Mat& ignored_region, const StandingCheckOptions& options);

// One check per window, given as (first, last) frame indices into `times` [s, increasing];
// `read(i)` gives frame i (8-bit grey or BGR; empty: unreadable, the pair tells nothing), read in
// order; `ignored_region` (nonzero: left out) may be empty.
std::vector<WindowMotionCheck> check_standing(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<std::pair<std::size_t, std::size_t>>& windows, const cv::Mat& ignored_region,
    const StandingCheckOptions& options = {});

}  // namespace x2car::camera
