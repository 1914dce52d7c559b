// Corners of one frame followed into a later one: what the facing check (facing_check.hpp) and
// the standing check (standing_check.hpp) measure of a pair of frames.
#pragma once

#include <cstddef>
#include <opencv2/core/types.hpp>
#include <utility>
#include <vector>

namespace cv {
class Mat;
}  // namespace cv

namespace x2car::camera {

struct CornerTrack {
  cv::Point2f from;       // in the earlier frame [px, as decoded]
  cv::Point2f to;         // in the later one
  std::size_t point = 0;  // the index of `from` among the points given (or corners found)
};

// `points` of `earlier` tracked into `later` with pyramidal LK (a `window_px` square window,
// `pyramid_levels` levels above the image: each doubles the motion it follows, and widens what
// the window sees at the top level, so that a moving object drags still points near it) and back
// again; those that come back within 1 px of where they started. Both frames 8-bit grey of one
// size.
std::vector<CornerTrack> track_points(const cv::Mat& earlier, const cv::Mat& later,
                                      const std::vector<cv::Point2f>& points, int window_px = 21,
                                      int pyramid_levels = 3);

// Corners of `earlier` (cv::goodFeaturesToTrack: at most `max_corners`, 8 px apart, outside the
// nonzero pixels of `ignored_region` when it is not empty), tracked into `later` with pyramidal
// LK and back again (track_points).
std::vector<CornerTrack> track_corners(const cv::Mat& earlier, const cv::Mat& later,
                                       const cv::Mat& ignored_region, int max_corners);

// Whether every step of `step` frames from `first` to `last` (indices into `times` [s]) spans at
// most `max_gap_s`: no frame dropped or stop in the recording between frames tracked together.
bool steps_within_gap(const std::vector<double>& times, std::size_t first, std::size_t last,
                      std::size_t step, double max_gap_s);

// The pairs (i, j) of frames first..last (indices into `times` [s], increasing) that pair each
// frame i with the first frame j at least `interval_s` later, when that is at most `max_gap_s`
// later (a frame dropped, a stop in the recording), in order.
std::vector<std::pair<std::size_t, std::size_t>> frame_pairs_in(const std::vector<double>& times,
                                                                std::size_t first, std::size_t last,
                                                                double interval_s,
                                                                double max_gap_s);

// `wanted` indices spread evenly over 0..count-1, in order, the first and the last among them (all
// of them when count <= wanted; none when count is 0).
std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t wanted);

}  // namespace x2car::camera
