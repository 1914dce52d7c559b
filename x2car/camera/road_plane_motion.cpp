#include "x2car/camera/road_plane_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "x2car/camera/grey_image.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void RoadPlaneMotionOptions::Check() const {
  const OptionsCheck check("RoadPlaneMotionOptions");
  check.in_range("tracked_frames", tracked_frames, 2, 10);
  check.at_least("max_features", max_features, 8);
  check.in_range("feature_quality", feature_quality, 0.0, 1.0, Bounds::kOpenMin);
  check.positive("min_feature_distance_px", min_feature_distance_px);
  check.in_range("road_region_depression", road_region_depression, -kPi / 4.0, kPi / 4.0);
  check.at_least("tracking_window_px", tracking_window_px, 5);
  check.in_range("pyramid_levels", pyramid_levels, 0, 8);
  check.non_negative("max_lateral_over_height", max_lateral_over_height);
  check.non_negative("max_seed_travel_over_height", max_seed_travel_over_height);
  check.in_range("seeded_feature_quality", seeded_feature_quality, 0.0, 1.0, Bounds::kOpenMin);
  check.positive("max_forward_backward_px", max_forward_backward_px);
  check.positive("ransac_threshold_px", ransac_threshold_px);
  check.at_least("min_inliers", min_inliers, 8);
  check.non_negative("min_translation_over_height", min_translation_over_height);
  check.in_range("max_rotation", max_rotation, 0.0, kPi / 4.0, Bounds::kOpenMin);
  check.in_range("max_normal_tilt", max_normal_tilt, 0.0, kPi / 2.0, Bounds::kOpen);
  check.that(ignored_region.empty() || ignored_region.type() == CV_8UC1, "ignored_region",
             "must be an 8-bit single-channel image");
}

namespace {

Eigen::Vector3d vector_from_cv(const cv::Mat& vector) {
  return {vector.at<double>(0), vector.at<double>(1), vector.at<double>(2)};
}

// Lucas-Kanade's window and its stop (OpenCV's defaults: 30 steps or 0.01 px).
cv::Size tracking_window(const RoadPlaneMotionOptions& options) {
  return {options.tracking_window_px, options.tracking_window_px};
}
cv::TermCriteria tracking_criteria() {
  return {cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01};
}

// An image's Lucas-Kanade pyramid with its derivatives, `levels` above the image
// (cv::buildOpticalFlowPyramid), built once for every tracking pass that reads the image. Given an
// image, calcOpticalFlowPyrLK builds the very same pyramid on each call, and each image here is
// read by two to six passes (forward and back, several seeds): the tracks are the same, the work
// is not repeated.
using Pyramid = std::vector<cv::Mat>;

Pyramid lk_pyramid(const cv::Mat& image, const RoadPlaneMotionOptions& options, int levels) {
  Pyramid pyramid;
  cv::buildOpticalFlowPyramid(image, pyramid, tracking_window(options), levels, true);
  return pyramid;
}

// Whether a point tracked forward is kept: found, and inside an image of `size`.
bool tracked_inside(unsigned char found, const cv::Point2f& point, const cv::Size& size) {
  return found && point.x >= 0.0f && point.y >= 0.0f &&
         point.x <= static_cast<float>(size.width - 1) &&
         point.y <= static_cast<float>(size.height - 1);
}

// The forward-backward check of a tracking `from` -> `to`: `alive[i]` says whether point i,
// started at `start[i]` and found at `tracked[i]` (`found[i]`, inside an image of `size`), tracks
// back from there to within max_forward_backward_px of its start. Only the points kept forward are
// tracked back: Lucas-Kanade tracks each point on its own, so theirs are the tracks a backward
// pass over all of them gives, at the cost of the survivors only.
void check_back(const Pyramid& from, const Pyramid& to, const cv::Size& size,
                const RoadPlaneMotionOptions& options, int levels,
                const std::vector<cv::Point2f>& start, const std::vector<cv::Point2f>& tracked,
                const std::vector<unsigned char>& found, std::vector<unsigned char>& alive) {
  std::vector<std::size_t> kept;
  std::vector<cv::Point2f> kept_tracked;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    alive[i] = 0;
    if (!tracked_inside(found[i], tracked[i], size)) continue;
    kept.push_back(i);
    kept_tracked.push_back(tracked[i]);
  }
  if (kept.empty()) return;
  std::vector<cv::Point2f> back;
  std::vector<unsigned char> back_found;
  cv::calcOpticalFlowPyrLK(to, from, kept_tracked, back, back_found, cv::noArray(),
                           tracking_window(options), levels, tracking_criteria());
  const double max_miss_squared = options.max_forward_backward_px * options.max_forward_backward_px;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const cv::Point2f miss = back[k] - start[kept[k]];
    alive[kept[k]] = back_found[k] && miss.dot(miss) <= max_miss_squared;
  }
}

// One Lucas-Kanade step, forward and back: `points` move into `to` (an image of `size`); those
// lost, or not back at their start within max_forward_backward_px, or outside the image, are
// marked in `alive`.
void track_step(const Pyramid& from, const Pyramid& to, const cv::Size& size,
                const RoadPlaneMotionOptions& options, std::vector<cv::Point2f>& points,
                std::vector<unsigned char>& alive) {
  std::vector<cv::Point2f> forward;
  std::vector<unsigned char> forward_ok;
  cv::calcOpticalFlowPyrLK(from, to, points, forward, forward_ok, cv::noArray(),
                           tracking_window(options), options.pyramid_levels, tracking_criteria());
  std::vector<unsigned char> checked(points.size());
  check_back(from, to, size, options, options.pyramid_levels, points, forward, forward_ok, checked);
  for (std::size_t i = 0; i < points.size(); ++i) {
    alive[i] = alive[i] && checked[i];
    points[i] = forward[i];
  }
}

// The homography (in pixels, RANSAC) that the live tracks fit; empty with fewer than
// `min_inliers` of them. A looser threshold than step 3's: these tracks only seed the next ones.
cv::Mat homography_of_live_tracks(const RoadPlaneMotionOptions& options,
                                  const std::vector<cv::Point2f>& corners,
                                  const std::vector<cv::Point2f>& points,
                                  const std::vector<unsigned char>& alive) {
  std::vector<cv::Point2f> from;
  std::vector<cv::Point2f> to;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (!alive[i]) continue;
    from.push_back(corners[i]);
    to.push_back(points[i]);
  }
  if (from.size() < static_cast<std::size_t>(std::max(options.min_inliers, 8))) return {};
  return cv::findHomography(from, to, cv::RANSAC, 2.0 * options.ransac_threshold_px);
}

// Step 1b (RoadPlaneMotionOptions::prewarp): the oldest image warped by `homography` (pixels) into
// the current one's view, and each corner tracked again from its predicted place, forward and
// back, through `levels` pyramid levels above the image (`current` has at least as many). Through
// a lens with distortion the pixels' homography is only a prediction; the second tracking absorbs
// the rest.
void retrack_through_homography(const cv::Mat& oldest, const Pyramid& current,
                                const RoadPlaneMotionOptions& options, const cv::Mat& homography,
                                int levels, const std::vector<cv::Point2f>& corners,
                                std::vector<cv::Point2f>& points,
                                std::vector<unsigned char>& alive) {
  cv::Mat warped_image;
  cv::warpPerspective(oldest, warped_image, homography, oldest.size(), cv::INTER_LINEAR);
  const Pyramid warped = lk_pyramid(warped_image, options, levels);
  std::vector<cv::Point2f> predicted;
  cv::perspectiveTransform(corners, predicted, homography);
  std::vector<cv::Point2f> tracked = predicted;
  std::vector<unsigned char> forward_ok;
  cv::calcOpticalFlowPyrLK(warped, current, predicted, tracked, forward_ok, cv::noArray(),
                           tracking_window(options), levels, tracking_criteria(),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  check_back(warped, current, oldest.size(), options, levels, predicted, tracked, forward_ok,
             alive);
  points = tracked;
}

// How well a homography (pixels) maps the oldest image onto the current one over the road region:
// the zero-mean normalised correlation of the warped oldest image and the current one, both at
// half resolution (the road's texture at the tracker's scale, at a quarter of the cost). The seed
// search asks it for some 80 homographies a frame, so an image's sums (of w, w^2 and w c over the
// region) are taken in one pass, row by row over the region's runs, in integers: exactly the sums
// cv::meanStdDev and cv::mean form in doubles, at a fraction of their four passes.
class RoadCorrelation {
 public:
  RoadCorrelation(const cv::Mat& oldest, const cv::Mat& current, const cv::Mat& road_mask) {
    cv::pyrDown(oldest, oldest_half_);
    cv::Mat current_half;
    cv::pyrDown(current, current_half);
    cv::Mat mask_half;
    cv::resize(road_mask, mask_half, current_half.size(), 0.0, 0.0, cv::INTER_NEAREST);
    box_ = cv::boundingRect(mask_half);
    if (box_.area() == 0) return;
    const cv::Mat mask = mask_half(box_);
    current_ = current_half(box_);
    // The region's runs of pixels, row by row, each short enough for 32-bit sums
    // (255^2 x 32767 < 2^31).
    constexpr int kLongestRun = 32767;
    for (int row = 0; row < mask.rows; ++row) {
      const auto* in_mask = mask.ptr<unsigned char>(row);
      for (int column = 0; column < mask.cols;) {
        if (!in_mask[column]) {
          ++column;
          continue;
        }
        const int first = column;
        while (column < mask.cols && in_mask[column] && column - first < kLongestRun) ++column;
        runs_.push_back({row, first, column});
        pixels_ += column - first;
      }
    }
    const Sums current_sums = sums(current_);
    current_mean_ = mean(current_sums);
    current_sd_ = standard_deviation(current_sums);
    // Pixel (u, v) of the half image is (2u, 2v) of the whole one; the box starts at its corner.
    box_from_full_ << 0.5, 0.0, -box_.x, 0.0, 0.5, -box_.y, 0.0, 0.0, 1.0;
    half_to_full_ << 2.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0;
  }

  // In [-1, 1]; -1 when the region is empty or flat.
  double operator()(const Eigen::Matrix3d& current_from_oldest_px) {
    if (pixels_ == 0 || current_sd_ <= 0.0) return -1.0;
    const Eigen::Matrix3d in_box = box_from_full_ * current_from_oldest_px * half_to_full_;
    cv::eigen2cv(in_box, in_box_cv_);
    cv::warpPerspective(oldest_half_, warped_, in_box_cv_, box_.size(), cv::INTER_LINEAR,
                        cv::BORDER_REPLICATE);
    const Sums warped_sums = sums(warped_);
    const double sd = standard_deviation(warped_sums);
    if (sd <= 0.0) return -1.0;
    const double product_mean = static_cast<double>(warped_sums.product) * scale();
    return (product_mean - mean(warped_sums) * current_mean_) / (sd * current_sd_);
  }

 private:
  struct Run {
    int row;
    int first;
    int end;
  };
  struct Sums {
    std::int64_t value = 0;
    std::int64_t squared = 0;
    std::int64_t product = 0;  // with the current image
  };

  // An 8-bit image of the box: its sums over the region.
  Sums sums(const cv::Mat& image) const {
    Sums total;
    for (const Run& run : runs_) {
      const auto* values = image.ptr<unsigned char>(run.row);
      const auto* current = current_.ptr<unsigned char>(run.row);
      std::int32_t run_value = 0;
      std::int32_t run_squared = 0;
      std::int32_t run_product = 0;
      for (int column = run.first; column < run.end; ++column) {
        const std::int32_t value = values[column];
        run_value += value;
        run_squared += value * value;
        run_product += value * static_cast<std::int32_t>(current[column]);
      }
      total.value += run_value;
      total.squared += run_squared;
      total.product += run_product;
    }
    return total;
  }
  // Mean and standard deviation as cv::meanStdDev finishes its sums.
  double scale() const { return 1.0 / static_cast<double>(pixels_); }
  double mean(const Sums& sums) const { return static_cast<double>(sums.value) * scale(); }
  double standard_deviation(const Sums& sums) const {
    const double average = mean(sums);
    return std::sqrt(
        std::max(static_cast<double>(sums.squared) * scale() - average * average, 0.0));
  }

  cv::Mat oldest_half_;
  cv::Rect box_;
  cv::Mat current_;  // the current image's box, 8-bit
  std::vector<Run> runs_;
  std::int64_t pixels_ = 0;
  double current_mean_ = 0.0;
  double current_sd_ = 0.0;
  Eigen::Matrix3d box_from_full_;
  Eigen::Matrix3d half_to_full_;
  cv::Mat in_box_cv_;
  cv::Mat warped_;
};

// Step 1b's second seed (RoadPlaneMotionOptions::max_seed_travel_over_height): the road's
// homography for straight travel s along the car's forward direction f over the road (unit normal
// n, pointing down, at the camera's height h), X2 = X1 - s f and n^T X1 = h, so
// H = I - (s / h) f n^T, with f and n from the guide (else the optical axis and +y) and s / h
// searched on a grid 5 % apart for the best RoadCorrelation (refined by a parabola). nullopt when
// the search is off or nothing correlates.
std::optional<Eigen::Matrix3d> searched_seed(RoadCorrelation& correlation,
                                             const core::CameraIntrinsics& intrinsics,
                                             const RoadPlaneMotionOptions& options,
                                             const std::optional<SequenceGuide>& guide) {
  const double first = std::max(options.min_translation_over_height, 0.05);
  if (options.max_seed_travel_over_height <= first) return std::nullopt;
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d down = Eigen::Vector3d::UnitY();
  if (guide) {
    const std::optional<Eigen::Matrix3d> vehicle_from_camera =
        vehicle_from_camera_rotation(guide->vanishing_point_px, guide->horizon_line, camera_matrix);
    if (vehicle_from_camera) {
      const Eigen::Matrix3d optical_from_vehicle =
          (*vehicle_from_camera * body_from_optical()).transpose();
      forward = optical_from_vehicle.col(0);
      down = -optical_from_vehicle.col(2);
    }
  }
  const Eigen::Matrix3d optical_from_pixel = camera_matrix.inverse();
  const auto pixel_homography = [&](double log_travel_over_height) {
    const Eigen::Matrix3d plane =
        Eigen::Matrix3d::Identity() - std::exp(log_travel_over_height) * forward * down.transpose();
    return Eigen::Matrix3d(camera_matrix * plane * optical_from_pixel);
  };
  const double step = std::log(1.05);
  const int candidates =
      static_cast<int>(std::floor(std::log(options.max_seed_travel_over_height / first) / step)) +
      1;
  std::vector<double> scores(static_cast<std::size_t>(candidates));
  for (int k = 0; k < candidates; ++k) {
    scores[static_cast<std::size_t>(k)] = correlation(pixel_homography(std::log(first) + k * step));
  }
  const auto best = std::max_element(scores.begin(), scores.end());
  if (*best <= 0.0) return std::nullopt;
  // The parabola through the best and its neighbours.
  double offset = 0.0;
  if (best != scores.begin() && best + 1 != scores.end()) {
    const double left = *(best - 1);
    const double right = *(best + 1);
    const double curvature = left - 2.0 * *best + right;
    if (curvature < 0.0) offset = std::clamp(0.5 * (left - right) / curvature, -0.5, 0.5);
  }
  const double k = static_cast<double>(best - scores.begin()) + offset;
  return pixel_homography(std::log(first) + k * step);
}

// The road region of step 1: below the row of `road_region_depression` under the road's horizon,
// inside the wedge of `max_lateral_over_height` about the principal point. For a level camera the
// road's horizon is the principal point's row; with a guide (`road_region_at_guide`) it is the
// guide's vanishing point's row where that lies lower (a camera pitched up).
cv::Mat road_region_mask(const cv::Size& size, const core::CameraIntrinsics& intrinsics,
                         const RoadPlaneMotionOptions& options,
                         const std::optional<SequenceGuide>& guide) {
  double horizon_elevation = 0.0;  // below the optical axis [rad]
  if (guide && options.road_region_at_guide && guide->vanishing_point_px.allFinite()) {
    horizon_elevation =
        std::max(0.0, std::atan((guide->vanishing_point_px.y() - intrinsics.cy) / intrinsics.fy));
  }
  const double top_row =
      intrinsics.cy +
      intrinsics.fy *
          std::tan(std::min(horizon_elevation + options.road_region_depression, 0.49 * kPi));
  const int top = std::clamp(static_cast<int>(std::ceil(top_row)), 0, size.height - 1);
  cv::Mat mask = cv::Mat::zeros(size, CV_8U);
  mask.rowRange(top, size.height).setTo(255);
  if (options.max_lateral_over_height > 0.0) {
    // For a level camera a road point y to the side, h below and Z ahead is imaged at
    // u - cx = fx y / Z, v - cy = fy h / Z: |u - cx| / (v - cy) = (fx / fy) |y| / h.
    for (int v = top; v < size.height; ++v) {
      const double half_px =
          options.max_lateral_over_height * (v - intrinsics.cy) * intrinsics.fx / intrinsics.fy;
      const int first =
          std::clamp(static_cast<int>(std::ceil(intrinsics.cx - half_px)), 0, size.width);
      const int last =
          std::clamp(static_cast<int>(std::floor(intrinsics.cx + half_px)) + 1, first, size.width);
      mask.row(v).colRange(0, first).setTo(0);
      mask.row(v).colRange(last, size.width).setTo(0);
    }
  }
  return mask;
}

// The tracks alive, as RoadTracks.
RoadTracks live_tracks(const std::vector<cv::Point2f>& corners,
                       const std::vector<cv::Point2f>& points,
                       const std::vector<unsigned char>& alive) {
  RoadTracks tracks;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (!alive[i]) continue;
    tracks.oldest_px.emplace_back(corners[i].x, corners[i].y);
    tracks.current_px.emplace_back(points[i].x, points[i].y);
  }
  return tracks;
}

// Step 1: Shi-Tomasi corners in the road region of the oldest frame, tracked frame by frame into
// the current one, then (prewarp) again through the homography of those tracks.
// `pyramids` are the greys', as many.
RoadTracks track_road_points(const std::vector<cv::Mat>& greys,
                             const std::vector<Pyramid>& pyramids,
                             const std::vector<cv::Point2f>& corners,
                             const RoadPlaneMotionOptions& options) {
  const cv::Mat& oldest = greys.front();
  if (corners.empty()) return {};
  std::vector<cv::Point2f> points = corners;
  std::vector<unsigned char> alive(points.size(), 1);
  for (std::size_t k = 1; k < greys.size(); ++k) {
    track_step(pyramids[k - 1], pyramids[k], oldest.size(), options, points, alive);
  }
  if (options.prewarp) {
    const cv::Mat homography = homography_of_live_tracks(options, corners, points, alive);
    if (!homography.empty()) {
      retrack_through_homography(oldest, pyramids.back(), options, homography, 1, corners, points,
                                 alive);
    }
  }
  return live_tracks(corners, points, alive);
}

// Step 1 from the searched seed (RoadPlaneMotionOptions::max_seed_travel_over_height): corners
// (down to `seeded_feature_quality`) tracked from where the seed puts them through two pyramid
// levels (the guide's directions are a few tenths of a degree off, the nominal ones a few
// degrees), then once more through the homography of those tracks, as step 1b. `corners` is not
// empty.
RoadTracks track_from_seed(const cv::Mat& oldest, const Pyramid& current,
                           const std::vector<cv::Point2f>& corners,
                           const RoadPlaneMotionOptions& options, const Eigen::Matrix3d& seed_px) {
  std::vector<cv::Point2f> points(corners.size());
  std::vector<unsigned char> alive(corners.size(), 0);
  cv::Mat seed;
  cv::eigen2cv(seed_px, seed);
  retrack_through_homography(oldest, current, options, seed, 2, corners, points, alive);
  const cv::Mat refined = homography_of_live_tracks(options, corners, points, alive);
  if (!refined.empty()) {
    retrack_through_homography(oldest, current, options, refined, 1, corners, points, alive);
  }
  return live_tracks(corners, points, alive);
}

// Step 4: of the decomposition's solutions, the one whose normal points down the most; nullopt
// when none is within max_normal_tilt of +y.
struct PlaneMotion {
  Eigen::Matrix3d rotation;     // R: X2 = R X1 + t
  Eigen::Vector3d translation;  // t / d
  Eigen::Vector3d normal;       // n in the first frame, unit, pointing down to the road
};

std::optional<PlaneMotion> decompose(const cv::Mat& homography,
                                     const RoadPlaneMotionOptions& options) {
  std::vector<cv::Mat> rotations;
  std::vector<cv::Mat> translations;
  std::vector<cv::Mat> normals;
  cv::decomposeHomographyMat(homography, cv::Mat::eye(3, 3, CV_64F), rotations, translations,
                             normals);
  std::optional<PlaneMotion> best;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const Eigen::Vector3d normal = vector_from_cv(normals[i]).normalized();
    if (!normal.allFinite()) continue;
    if (best && normal.y() <= best->normal.y()) continue;
    best = PlaneMotion{Eigen::Matrix3d::Zero(), vector_from_cv(translations[i]), normal};
    cv::cv2eigen(rotations[i], best->rotation);
  }
  if (!best || std::acos(std::clamp(best->normal.y(), -1.0, 1.0)) > options.max_normal_tilt) {
    return std::nullopt;
  }
  return best;
}

}  // namespace

namespace {

// Steps 2-5 (road_plane_from_tracks); when the estimate is usable, `current_from_oldest_px` is set
// to the road's homography in pixels (K H K^-1, ignoring the lens's distortion).
FrameEstimate fit_plane_to_tracks(const std::vector<Eigen::Vector2d>& previous_px,
                                  const std::vector<Eigen::Vector2d>& current_px,
                                  const core::CameraIntrinsics& intrinsics,
                                  const RoadPlaneMotionOptions& options,
                                  Eigen::Matrix3d& current_from_oldest_px) {
  const std::size_t count = std::min(previous_px.size(), current_px.size());
  if (count < static_cast<std::size_t>(std::max(options.min_inliers, 8))) {
    FrameEstimate rejected = rejected_frame(FrameRejection::kTooFewTracks);
    rejected.segments = static_cast<int>(count);
    return rejected;
  }
  // Step 2: normalised, undistorted image points.
  std::vector<cv::Point2d> previous_points;
  std::vector<cv::Point2d> current_points;
  previous_points.reserve(count);
  current_points.reserve(count);
  const bool distorted = intrinsics.distortion_model != core::DistortionModel::kNone;
  const auto normalise = [&](const Eigen::Vector2d& pixel) {
    const Eigen::Vector2d undistorted =
        distorted ? core::undistort_pixel(intrinsics, pixel) : pixel;
    return cv::Point2d((undistorted.x() - intrinsics.cx) / intrinsics.fx,
                       (undistorted.y() - intrinsics.cy) / intrinsics.fy);
  };
  for (std::size_t i = 0; i < count; ++i) {
    previous_points.push_back(normalise(previous_px[i]));
    current_points.push_back(normalise(current_px[i]));
  }
  // Step 3: the road's homography. OpenCV's RANSAC draws from its own fixed-seed generator, so a
  // pair always gives the same answer, whichever thread runs it.
  std::vector<unsigned char> inlier_mask;
  const double threshold = options.ransac_threshold_px / intrinsics.fx;
  const cv::Mat homography = cv::findHomography(previous_points, current_points, cv::RANSAC,
                                                threshold, inlier_mask, 2000, 0.999);
  const int inliers = static_cast<int>(std::count(inlier_mask.begin(), inlier_mask.end(), 1));
  FrameEstimate estimate;
  estimate.segments = static_cast<int>(count);
  estimate.road_inliers = inliers;
  estimate.horizon_inliers = inliers;
  if (homography.empty() || inliers < options.min_inliers) {
    estimate.rejection = FrameRejection::kNoRoadPlane;
    return estimate;
  }
  // Step 4.
  const std::optional<PlaneMotion> motion = decompose(homography, options);
  if (!motion) {
    estimate.rejection = FrameRejection::kNoRoadPlane;
    return estimate;
  }
  const Eigen::AngleAxisd rotation(motion->rotation);
  if (!motion->translation.allFinite() || !std::isfinite(rotation.angle()) ||
      std::abs(rotation.angle()) > options.max_rotation) {
    estimate.rejection = FrameRejection::kNoRoadPlane;
    return estimate;
  }
  if (motion->translation.norm() < options.min_translation_over_height) {
    estimate.rejection = FrameRejection::kTooLittleMotion;
    return estimate;
  }
  // Step 5: the chord from the first camera centre to the second, in the first frame, turned on
  // by half the camera's turn (R maps the first frame's coordinates to the second's, so the camera
  // turned by R^T): the heading at the current frame; then both directions in the current frame.
  const Eigen::Vector3d chord = -(motion->rotation.transpose() * motion->translation);
  const Eigen::Matrix3d half_turn =
      Eigen::AngleAxisd(-0.5 * rotation.angle(), rotation.axis()).toRotationMatrix();
  Eigen::Vector3d forward = motion->rotation * (half_turn * chord.normalized());
  // A camera that looks back sees the car travel away from its view: the travel's line meets the
  // image at the same vanishing point from behind. Its direction is taken as the one in front, as
  // the geometric estimator's ray is; the facing check (facing_check.hpp) tells them apart.
  if (forward.z() < 0.0) forward = -forward;
  const Eigen::Vector3d up = -(motion->rotation * motion->normal);
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  const std::optional<Eigen::Vector3d> horizon = horizon_from_up(up, camera_matrix);
  if (forward.z() <= 1e-6 || !horizon) {
    estimate.rejection = FrameRejection::kNoRoadPlane;
    return estimate;
  }
  const Eigen::Vector3d vanishing = camera_matrix * forward;
  estimate.road_vanishing_point_px = vanishing.head<2>() / vanishing.z();
  estimate.horizon_line = *horizon;
  estimate.horizon_source = HorizonSource::kRoadPlaneMotion;
  // The camera turned by R^T, whose rotation vector is -angle * axis; up is -n (in either frame:
  // the axis is R's fixed direction, so its component along n does not depend on the frame).
  estimate.pair_motion =
      CameraPairMotion{.turn_about_up = rotation.angle() * rotation.axis().dot(motion->normal),
                       .travel_over_height = motion->translation.norm()};
  estimate.quality = static_cast<double>(inliers) / static_cast<double>(count);
  // RMS transfer error of the inliers [rad at the image centre, like the geometric residual].
  Eigen::Matrix3d h;
  cv::cv2eigen(homography, h);
  double sum_squared = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!inlier_mask[i]) continue;
    const Eigen::Vector3d mapped =
        h * Eigen::Vector3d(previous_points[i].x, previous_points[i].y, 1.0);
    const Eigen::Vector2d miss =
        mapped.head<2>() / mapped.z() - Eigen::Vector2d(current_points[i].x, current_points[i].y);
    sum_squared += miss.squaredNorm();
  }
  estimate.road_residual_rms = std::sqrt(sum_squared / inliers);
  current_from_oldest_px = camera_matrix * h * camera_matrix.inverse();
  return estimate;
}

}  // namespace

// The mask's bounding box grown by 3 pixels: a pixel's response (3x3 derivatives summed over 3x3)
// and its local-maximum test (3x3) read up to 3 pixels around it, and a sub-image's filters read
// its parent's pixels, so every response the search keeps is the whole image's; equal responses
// keep their row-by-row order.
void corners_in_mask(const cv::Mat& image, const cv::Mat& mask, int max_corners, double quality,
                     double min_distance_px, std::vector<cv::Point2f>& corners,
                     std::vector<float>& responses) {
  corners.clear();
  responses.clear();
  const cv::Rect mask_box = cv::boundingRect(mask);
  if (mask_box.area() == 0) return;
  constexpr int kMargin = 3;
  const cv::Rect box = cv::Rect(mask_box.x - kMargin, mask_box.y - kMargin,
                                mask_box.width + 2 * kMargin, mask_box.height + 2 * kMargin) &
                       cv::Rect(0, 0, image.cols, image.rows);
  cv::goodFeaturesToTrack(image(box), corners, max_corners, quality, min_distance_px, mask(box),
                          responses);
  for (cv::Point2f& corner : corners) {
    corner.x += static_cast<float>(box.x);
    corner.y += static_cast<float>(box.y);
  }
}

FrameEstimate road_plane_from_tracks(const std::vector<Eigen::Vector2d>& previous_px,
                                     const std::vector<Eigen::Vector2d>& current_px,
                                     const core::CameraIntrinsics& intrinsics,
                                     const RoadPlaneMotionOptions& options) {
  Eigen::Matrix3d unused;
  return fit_plane_to_tracks(previous_px, current_px, intrinsics, options, unused);
}

namespace {

// Frames -> 8-bit greys of the intrinsics' size, or why not.
std::optional<FrameRejection> grey_frames(const std::vector<cv::Mat>& frames,
                                          const core::CameraIntrinsics& intrinsics,
                                          std::vector<cv::Mat>& greys) {
  if (frames.size() < 2) return FrameRejection::kNoPreviousFrame;
  greys.reserve(frames.size());
  for (const cv::Mat& image : frames) {
    if (image.empty()) return FrameRejection::kUnreadableImage;
    if (image.cols != intrinsics.width || image.rows != intrinsics.height) {
      return FrameRejection::kWrongImageSize;
    }
    greys.push_back(grey_8bit(image));
  }
  return std::nullopt;
}

// Steps 1-5 from the tracked seed and from the searched one (max_seed_travel_over_height): at
// highway speed the first tracks give no homography, or a wrong one that the second tracking then
// follows, and its fit can be usable yet wrong; only the comparison tells. Of the two fits the one
// whose homography maps the road better (RoadCorrelation) is kept; `used` receives the tracks of
// the estimate returned.
FrameEstimate fit_road_plane(const std::vector<cv::Mat>& greys,
                             const core::CameraIntrinsics& intrinsics,
                             const RoadPlaneMotionOptions& options,
                             const std::optional<SequenceGuide>& guide, RoadTracks& used) {
  const cv::Mat& oldest = greys.front();
  const cv::Mat& current = greys.back();
  if (!options.ignored_region.empty() && options.ignored_region.size() != oldest.size()) {
    return rejected_frame(FrameRejection::kWrongImageSize);
  }
  cv::Mat mask = road_region_mask(oldest.size(), intrinsics, options, guide);
  if (!options.ignored_region.empty()) mask.setTo(0, options.ignored_region);
  // The corners down to the weaker of the two qualities, strongest first: those of the tracked
  // seed (feature_quality) are a prefix of them (goodFeaturesToTrack's order and suppression).
  std::vector<cv::Point2f> corners;
  std::vector<float> corner_quality;
  corners_in_mask(oldest, mask, options.max_features,
                  std::min(options.feature_quality, options.seeded_feature_quality),
                  options.min_feature_distance_px, corners, corner_quality);
  // Each frame's pyramid, for every pass that tracks out of it or into it; the current one's deep
  // enough for the second trackings' two levels too.
  std::vector<Pyramid> pyramids;
  if (!corners.empty()) {
    for (const cv::Mat& grey : greys) {
      pyramids.push_back(lk_pyramid(grey, options, std::max(options.pyramid_levels, 2)));
    }
  }
  const auto strong_end = std::find_if(
      corner_quality.begin(), corner_quality.end(),
      [&](float quality) { return quality < options.feature_quality * corner_quality.front(); });
  const std::vector<cv::Point2f> strong_corners(
      corners.begin(), corners.begin() + (strong_end - corner_quality.begin()));
  used = track_road_points(greys, pyramids, strong_corners, options);
  Eigen::Matrix3d tracked_homography;
  FrameEstimate estimate =
      fit_plane_to_tracks(used.oldest_px, used.current_px, intrinsics, options, tracked_homography);
  if (!options.prewarp || options.max_seed_travel_over_height <= 0.0 ||
      estimate.rejection == FrameRejection::kTooLittleMotion) {
    return estimate;
  }
  if (options.seeded_feature_quality > options.feature_quality) corners = strong_corners;
  if (corners.empty()) return estimate;  // nothing to track from a searched seed
  RoadCorrelation correlation(oldest, current, mask);
  const std::optional<Eigen::Matrix3d> seed =
      searched_seed(correlation, intrinsics, options, guide);
  if (!seed) return estimate;
  const double tracked_correlation = estimate.usable() ? correlation(tracked_homography) : -1.0;
  RoadTracks searched = track_from_seed(oldest, pyramids.back(), corners, options, *seed);
  Eigen::Matrix3d searched_homography;
  FrameEstimate from_search = fit_plane_to_tracks(searched.oldest_px, searched.current_px,
                                                  intrinsics, options, searched_homography);
  if (!from_search.usable() || tracked_correlation >= correlation(searched_homography)) {
    return estimate;
  }
  used = std::move(searched);
  return from_search;
}

}  // namespace

FrameEstimate estimate_road_plane_motion(const std::vector<cv::Mat>& frames,
                                         const core::CameraIntrinsics& intrinsics,
                                         const RoadPlaneMotionOptions& options,
                                         const std::optional<SequenceGuide>& guide) {
  std::vector<cv::Mat> greys;
  if (const auto rejection = grey_frames(frames, intrinsics, greys)) {
    return rejected_frame(*rejection);
  }
  RoadTracks used;
  return fit_road_plane(greys, intrinsics, options, guide, used);
}

RoadTracks road_plane_tracks(const std::vector<cv::Mat>& frames,
                             const core::CameraIntrinsics& intrinsics,
                             const RoadPlaneMotionOptions& options,
                             const std::optional<SequenceGuide>& guide) {
  std::vector<cv::Mat> greys;
  RoadTracks used;
  if (!grey_frames(frames, intrinsics, greys)) {
    fit_road_plane(greys, intrinsics, options, guide, used);
  }
  return used;
}

SequenceEstimator make_road_plane_motion_estimator(const RoadPlaneMotionOptions& options) {
  options.Check();
  return [options](const std::vector<cv::Mat>& frames, const core::CameraIntrinsics& intrinsics,
                   const std::optional<SequenceGuide>& guide) {
    return estimate_road_plane_motion(frames, intrinsics, options, guide);
  };
}

}  // namespace x2car::camera
