#include "x2car/camera/corner_tracks.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace x2car::camera {

namespace {

// Corners tracked from the earlier frame to the later and back within this are kept [px].
constexpr float kMaxRoundTripPx = 1.0F;

}  // namespace

std::vector<CornerTrack> track_points(const cv::Mat& earlier, const cv::Mat& later,
                                      const std::vector<cv::Point2f>& points, int window_px,
                                      int pyramid_levels) {
  std::vector<CornerTrack> tracks;
  if (points.empty()) return tracks;
  std::vector<cv::Point2f> tracked;
  std::vector<cv::Point2f> back;
  std::vector<unsigned char> found;
  std::vector<unsigned char> found_back;
  std::vector<float> error;
  const cv::Size window(window_px, window_px);
  cv::calcOpticalFlowPyrLK(earlier, later, points, tracked, found, error, window, pyramid_levels);
  cv::calcOpticalFlowPyrLK(later, earlier, tracked, back, found_back, error, window,
                           pyramid_levels);
  tracks.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!found[i] || !found_back[i]) continue;
    const cv::Point2f round_trip = back[i] - points[i];
    if (std::hypot(round_trip.x, round_trip.y) > kMaxRoundTripPx) continue;
    tracks.push_back({points[i], tracked[i], i});
  }
  return tracks;
}

std::vector<CornerTrack> track_corners(const cv::Mat& earlier, const cv::Mat& later,
                                       const cv::Mat& ignored_region, int max_corners) {
  cv::Mat usable;
  if (!ignored_region.empty()) usable = ignored_region == 0;
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(earlier, corners, max_corners, 0.01, 8.0, usable);
  return track_points(earlier, later, corners);
}

bool steps_within_gap(const std::vector<double>& times, std::size_t first, std::size_t last,
                      std::size_t step, double max_gap_s) {
  for (std::size_t i = first + step; i <= last; i += step) {
    if (times[i] - times[i - step] > max_gap_s) return false;
  }
  return true;
}

std::vector<std::pair<std::size_t, std::size_t>> frame_pairs_in(const std::vector<double>& times,
                                                                std::size_t first, std::size_t last,
                                                                double interval_s,
                                                                double max_gap_s) {
  // Times are read to a microsecond: 0.2 s at 10 Hz is 2 frames, not 3.
  constexpr double kTimeSlack = 1e-6;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::size_t later = first;
  for (std::size_t i = first; i < last; ++i) {
    later = std::max(later, i + 1);
    while (later < last && times[later] - times[i] < interval_s - kTimeSlack) ++later;
    const double gap_s = times[later] - times[i];
    if (gap_s >= interval_s - kTimeSlack && gap_s <= max_gap_s) pairs.emplace_back(i, later);
  }
  return pairs;
}

std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t wanted) {
  wanted = std::min(count, wanted);
  std::vector<std::size_t> indices;
  indices.reserve(wanted);
  for (std::size_t k = 0; k < wanted; ++k) {
    indices.push_back(wanted == 1 ? 0 : k * (count - 1) / (wanted - 1));
  }
  return indices;
}

}  // namespace x2car::camera
