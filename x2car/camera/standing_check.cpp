#include "x2car/camera/standing_check.hpp"

#include <algorithm>
#include <cmath>

#include "x2car/camera/corner_tracks.hpp"
#include "x2car/camera/grey_image.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void StandingCheckOptions::Check() const {
  const OptionsCheck check("StandingCheckOptions");
  check.at_least("pairs_per_window", pairs_per_window, 1.0);
  check.positive("pair_interval_s", pair_interval_s);
  check.at_least("pair_max_gap_s", pair_max_gap_s, pair_interval_s);
  check.at_least("corners_per_pair", corners_per_pair, 8.0);
  check.positive("min_corner_motion_px", min_corner_motion_px);
  check.in_range("min_moving_corner_share", min_moving_corner_share, 0.0, 1.0, Bounds::kOpenMin);
}

namespace {

// A pair tells whether it moved only with this many tracked corners.
constexpr std::size_t kMinTrackedCorners = 8;

}  // namespace

std::optional<bool> pair_moved(const cv::Mat& earlier, const cv::Mat& later,
                               const cv::Mat& ignored_region, const StandingCheckOptions& options) {
  const std::vector<CornerTrack> tracks = track_corners(grey_8bit(earlier), grey_8bit(later),
                                                        ignored_region, options.corners_per_pair);
  if (tracks.size() < kMinTrackedCorners) return std::nullopt;
  std::size_t moving = 0;
  for (const CornerTrack& track : tracks) {
    const cv::Point2f step = track.to - track.from;
    if (std::hypot(step.x, step.y) >= options.min_corner_motion_px) ++moving;
  }
  return static_cast<double>(moving) >=
         options.min_moving_corner_share * static_cast<double>(tracks.size());
}

std::vector<WindowMotionCheck> check_standing(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<std::pair<std::size_t, std::size_t>>& windows, const cv::Mat& ignored_region,
    const StandingCheckOptions& options) {
  options.Check();
  std::vector<WindowMotionCheck> checks;
  checks.reserve(windows.size());
  for (const auto& [first, last] : windows) {
    WindowMotionCheck& check = checks.emplace_back();
    const std::vector<std::pair<std::size_t, std::size_t>> pairs =
        frame_pairs_in(times, first, last, options.pair_interval_s, options.pair_max_gap_s);
    const std::size_t wanted =
        std::min(pairs.size(), static_cast<std::size_t>(options.pairs_per_window));
    for (std::size_t k = 0; k < wanted; ++k) {
      // Evenly over the window, in order (a video decodes forward).
      const std::size_t index = wanted == 1 ? 0 : k * (pairs.size() - 1) / (wanted - 1);
      const cv::Mat earlier = read(pairs[index].first);
      const cv::Mat later = read(pairs[index].second);
      ++check.pairs;
      if (earlier.empty() || later.empty()) continue;
      const std::optional<bool> moved = pair_moved(earlier, later, ignored_region, options);
      if (!moved) continue;
      ++(*moved ? check.pairs_moved : check.pairs_stood);
    }
  }
  return checks;
}

}  // namespace x2car::camera
