#include "x2car/camera/facing_check.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "x2car/camera/corner_tracks.hpp"
#include "x2car/camera/grey_image.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"

namespace x2car::camera {

void FacingCheckOptions::Check() const {
  const OptionsCheck check("FacingCheckOptions");
  check.at_least("frame_pairs", frame_pairs, 1.0);
  check.at_least("corners_per_pair", corners_per_pair, 8.0);
  check.positive("min_radial_flow_px", min_radial_flow_px);
  check.non_negative("min_corner_motion_px", min_corner_motion_px);
  check.in_range("min_distance_from_vanishing_point", min_distance_from_vanishing_point, 0.0, 1.0);
  check.at_least("min_moving_pairs", min_moving_pairs, 1.0);
  check.in_range("min_agreement", min_agreement, 0.5, 1.0, Bounds::kOpenMin);
}

namespace {

// A pair votes only with this many moving corners.
constexpr std::size_t kMinMovingCorners = 8;

// The median displacement of the moving corners along the rays from the vanishing point [px] (+:
// out of it), nullopt when fewer than kMinMovingCorners were tracked.
std::optional<double> median_radial_flow(const cv::Mat& earlier, const cv::Mat& later,
                                         const core::CameraIntrinsics& intrinsics,
                                         const Eigen::Vector2d& vanishing_point_px,
                                         const cv::Mat& ignored_region,
                                         const FacingCheckOptions& options) {
  const std::vector<CornerTrack> tracks =
      track_corners(earlier, later, ignored_region, options.corners_per_pair);
  if (tracks.size() < kMinMovingCorners) return std::nullopt;
  const double min_distance = options.min_distance_from_vanishing_point * intrinsics.width;
  std::vector<double> radial;
  radial.reserve(tracks.size());
  for (const CornerTrack& track : tracks) {
    // Undistorted, where the vanishing point and straight rays live.
    const Eigen::Vector2d from = core::undistort_pixel(intrinsics, {track.from.x, track.from.y});
    const Eigen::Vector2d to = core::undistort_pixel(intrinsics, {track.to.x, track.to.y});
    const Eigen::Vector2d ray = from - vanishing_point_px;
    if (!ray.allFinite() || !to.allFinite() || ray.norm() < min_distance) continue;
    // A corner that stays (the car's own bonnet or bumper, a reflection in the windscreen, a
    // logo) says nothing about the travel, and enough of them would hold the median at 0.
    if ((to - from).norm() < options.min_corner_motion_px) continue;
    radial.push_back((to - from).dot(ray.normalized()));
  }
  if (radial.size() < kMinMovingCorners) return std::nullopt;
  return median(radial);
}

}  // namespace

FacingCheck check_facing(const std::function<cv::Mat(std::size_t)>& read,
                         const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                         const core::CameraIntrinsics& intrinsics,
                         const Eigen::Vector2d& vanishing_point_px, const cv::Mat& ignored_region,
                         const FacingCheckOptions& options) {
  options.Check();
  FacingCheck check;
  // Evenly over the pairs offered, in their order.
  for (const std::size_t index :
       evenly_spaced(pairs.size(), static_cast<std::size_t>(options.frame_pairs))) {
    const auto [earlier_index, later_index] = pairs[index];
    const cv::Mat earlier = read(earlier_index);
    const cv::Mat later = read(later_index);
    ++check.pairs;
    if (earlier.empty() || later.empty()) continue;
    const std::optional<double> flow =
        median_radial_flow(grey_8bit(earlier), grey_8bit(later), intrinsics, vanishing_point_px,
                           ignored_region, options);
    if (!flow || std::abs(*flow) < options.min_radial_flow_px) continue;
    ++(*flow > 0.0 ? check.expanding : check.contracting);
  }
  const std::size_t moving = check.expanding + check.contracting;
  if (moving < static_cast<std::size_t>(options.min_moving_pairs)) {
    check.facing = Facing::kUndecided;
  } else if (static_cast<double>(check.expanding) >=
             options.min_agreement * static_cast<double>(moving)) {
    check.facing = Facing::kAhead;
  } else if (static_cast<double>(check.contracting) >=
             options.min_agreement * static_cast<double>(moving)) {
    check.facing = Facing::kBack;
  } else {
    check.facing = Facing::kConflicting;
  }
  return check;
}

}  // namespace x2car::camera
