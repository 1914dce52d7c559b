#include "x2car/camera/standing_check.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "x2car/camera/corner_tracks.hpp"
#include "x2car/camera/grey_image.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"

namespace x2car::camera {

void StandingCheckOptions::Check() const {
  const OptionsCheck check("StandingCheckOptions");
  check.at_least("pairs_per_window", pairs_per_window, 1.0);
  check.positive("pair_interval_s", pair_interval_s);
  check.at_least("pair_max_gap_s", pair_max_gap_s, pair_interval_s);
  check.at_least("grid_columns", grid_columns, 1.0);
  check.at_least("grid_rows", grid_rows, 1.0);
  check.at_least("corners_per_cell", corners_per_cell, 1.0);
  check.at_least("min_cell_corners", min_cell_corners, 1.0);
  check.positive("min_corner_motion_px", min_corner_motion_px);
  check.in_range("min_moving_cell_share", min_moving_cell_share, 0.0, 1.0, Bounds::kOpenMin);
  check.at_least("min_counted_cells", min_counted_cells, 1.0);
}

namespace {

// Whether a pair of frames moved; nullopt when fewer than min_counted_cells cells had
// min_cell_corners corners found.
std::optional<bool> pair_moved(const cv::Mat& earlier, const cv::Mat& later,
                               const cv::Mat& ignored_region, const StandingCheckOptions& options) {
  const int columns = options.grid_columns;
  const int rows = options.grid_rows;
  std::vector<cv::Point2f> points;
  std::vector<int> cell_of_point;
  std::vector<cv::Point2f> found;
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      const cv::Rect cell(column * earlier.cols / columns, row * earlier.rows / rows,
                          (column + 1) * earlier.cols / columns - column * earlier.cols / columns,
                          (row + 1) * earlier.rows / rows - row * earlier.rows / rows);
      if (cell.width < 8 || cell.height < 8) continue;
      cv::Mat usable;
      if (!ignored_region.empty()) usable = ignored_region(cell) == 0;
      cv::goodFeaturesToTrack(earlier(cell), found, options.corners_per_cell, 0.01, 8.0, usable);
      for (const cv::Point2f& corner : found) {
        points.emplace_back(corner.x + static_cast<float>(cell.x),
                            corner.y + static_cast<float>(cell.y));
        cell_of_point.push_back(row * columns + column);
      }
    }
  }
  std::vector<std::vector<double>> motion(static_cast<std::size_t>(rows * columns));
  // One pyramid level: a still corner stays found beside a passing car, and one that moved more
  // than the window follows (~20 px) is lost, which says as much.
  for (const CornerTrack& track : track_points(earlier, later, points, 21, 1)) {
    const cv::Point2f step = track.to - track.from;
    motion[static_cast<std::size_t>(cell_of_point[track.point])].push_back(
        std::hypot(step.x, step.y));
  }
  std::vector<std::size_t> found_in_cell(motion.size(), 0);
  for (const int cell : cell_of_point) ++found_in_cell[static_cast<std::size_t>(cell)];
  int counted = 0;
  int moved = 0;
  for (std::size_t cell = 0; cell < motion.size(); ++cell) {
    if (found_in_cell[cell] < static_cast<std::size_t>(options.min_cell_corners)) continue;
    ++counted;
    // Most of its corners lost: what they were moved too far, or out of view, to be found again.
    const bool lost = 2 * motion[cell].size() < found_in_cell[cell];
    if (lost || median(motion[cell]) >= options.min_corner_motion_px) ++moved;
  }
  if (counted < options.min_counted_cells) return std::nullopt;
  return moved >= options.min_moving_cell_share * counted;
}

}  // namespace

std::vector<StandingCheck> check_standing(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<std::pair<std::size_t, std::size_t>>& windows, const cv::Mat& ignored_region,
    const StandingCheckOptions& options) {
  options.Check();
  std::vector<StandingCheck> checks;
  checks.reserve(windows.size());
  for (const auto& [first, last] : windows) {
    StandingCheck& check = checks.emplace_back();
    const std::vector<std::pair<std::size_t, std::size_t>> pairs =
        frame_pairs_in(times, first, last, options.pair_interval_s, options.pair_max_gap_s);
    // Evenly over the window, in order (a video decodes forward).
    for (const std::size_t index : evenly_spaced(pairs.size(), options.pairs_per_window)) {
      const cv::Mat earlier = read(pairs[index].first);
      const cv::Mat later = read(pairs[index].second);
      ++check.pairs;
      if (earlier.empty() || later.empty()) continue;
      const std::optional<bool> moved =
          pair_moved(grey_8bit(earlier), grey_8bit(later), ignored_region, options);
      if (!moved) continue;
      ++(*moved ? check.pairs_moved : check.pairs_stood);
    }
  }
  return checks;
}

}  // namespace x2car::camera
