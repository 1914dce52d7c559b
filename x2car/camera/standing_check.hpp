// Whether the car stood through a steady window, from the images' motion.
//
// The temporal filter takes a window whose per-frame angles hardly change for the car driving
// straight on a flat road (paper §IV-A: "If the Std falls below a threshold, we consider as the
// car is driving on a straight road"). A car standing at a light or in a queue passes that test
// without driving at all: its frames repeat one view (the same angles, a std near 0, so the
// window's weight in the average is the largest there is), and that view may be of a car waiting
// at an angle to its lane at a junction. With the car's motion known (`--ins`) such frames are
// gated by speed; without it, the images tell.
//
// How: frames about half a second apart are paired, and the image is cut into a grid of cells,
// each with its own corners (so that the strong corners of a text overlay burnt into a dashcam's
// video cannot take them all), tracked with LK both ways at one pyramid level (a still corner
// stays found beside a passing car; one that moved beyond ~20 px is lost). A cell moved when most
// of its corners were lost or the median displacement of its tracked ones reaches
// min_corner_motion_px. The car's own travel moves
// the whole scene, so most cells that hold texture; what stays put in a driving car's view (a
// bonnet, a dashboard, an overlay) holds some cells, and what moves past a standing car (people,
// traffic) a few. A pair moved when at least min_moving_cell_share of its cells with corners
// moved. A window stood when more than half of the pairs looked at stood: a pair that cannot tell
// (too few cells with corners: night, fog, a blank wall; an unreadable frame) never counts as
// standing.
#pragma once

#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
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
  // The grid of cells the image is cut into, and the corners looked for in each
  // (cv::goodFeaturesToTrack).
  int grid_columns = 4;
  int grid_rows = 4;
  int corners_per_cell = 12;
  // A cell counts when this many corners were found in it (a plain sky has none); it moved when
  // fewer than half of them were tracked (to the later frame and back within 1 px: corners that
  // moved too far for the tracker are lost) or min_corner_motion_px below holds.
  int min_cell_corners = 3;
  // A cell moved when its tracked corners moved by a median of at least this [px]: above the
  // camera's jitter on an idling engine and the tracker's noise (~0.05 px), below what a car
  // creeping at 1 m/s moves the near scene by in half a second.
  double min_corner_motion_px = 0.5;
  // A pair moved when at least this share of its counting cells moved, and tells when at least
  // min_counted_cells counted.
  double min_moving_cell_share = 1.0 / 3.0;
  int min_counted_cells = 3;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// What the pairs of one window showed.
struct StandingCheck {
  std::size_t pairs = 0;        // looked at
  std::size_t pairs_stood = 0;  // whose cells stayed put
  std::size_t pairs_moved = 0;  // whose cells moved; the rest told nothing (too few cells with
                                // corners, an unreadable frame)
  // More than half of the pairs looked at stood.
  bool stood() const { return 2 * pairs_stood > pairs; }
};

// One check per window, given as (first, last) frame indices into `times` [s, increasing],
// inclusive; `read(i)` gives frame i (8-bit grey or BGR; empty: unreadable, the pair tells
// nothing), read in order; `ignored_region` (nonzero: left out) may be empty.
std::vector<StandingCheck> check_standing(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<std::pair<std::size_t, std::size_t>>& windows, const cv::Mat& ignored_region,
    const StandingCheckOptions& options = {});

}  // namespace x2car::camera
