#include "x2car/camera/road_plane_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
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
}

namespace {

Eigen::Matrix3d from_cv(const cv::Mat& matrix) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = matrix.at<double>(r, c);
  }
  return out;
}

Eigen::Vector3d vector_from_cv(const cv::Mat& vector) {
  return {vector.at<double>(0), vector.at<double>(1), vector.at<double>(2)};
}

// One Lucas-Kanade step, forward and back: `points` move into `to`; those lost, or not back at
// their start within max_forward_backward_px, or outside the image, are marked in `alive`.
void track_step(const cv::Mat& from, const cv::Mat& to, const RoadPlaneMotionOptions& options,
                std::vector<cv::Point2f>& points, std::vector<unsigned char>& alive) {
  const cv::Size window(options.tracking_window_px, options.tracking_window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<cv::Point2f> forward;
  std::vector<cv::Point2f> back;
  std::vector<unsigned char> forward_ok;
  std::vector<unsigned char> back_ok;
  std::vector<float> errors;
  cv::calcOpticalFlowPyrLK(from, to, points, forward, forward_ok, errors, window,
                           options.pyramid_levels, criteria);
  cv::calcOpticalFlowPyrLK(to, from, forward, back, back_ok, errors, window, options.pyramid_levels,
                           criteria);
  const double max_miss_squared = options.max_forward_backward_px * options.max_forward_backward_px;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const cv::Point2f miss = back[i] - points[i];
    const cv::Point2f& p = forward[i];
    if (!forward_ok[i] || !back_ok[i] || miss.dot(miss) > max_miss_squared || p.x < 0.0f ||
        p.y < 0.0f || p.x > static_cast<float>(to.cols - 1) ||
        p.y > static_cast<float>(to.rows - 1)) {
      alive[i] = 0;
    }
    points[i] = p;
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
// back, through `levels` pyramid levels above the image. Through a lens with distortion the
// pixels' homography is only a prediction; the second tracking absorbs the rest. Returns how many
// tracks are alive.
int retrack_through_homography(const cv::Mat& oldest, const cv::Mat& current,
                               const RoadPlaneMotionOptions& options, const cv::Mat& homography,
                               int levels, const std::vector<cv::Point2f>& corners,
                               std::vector<cv::Point2f>& points,
                               std::vector<unsigned char>& alive) {
  cv::Mat warped;
  cv::warpPerspective(oldest, warped, homography, oldest.size(), cv::INTER_LINEAR);
  std::vector<cv::Point2f> predicted;
  cv::perspectiveTransform(corners, predicted, homography);
  std::vector<cv::Point2f> tracked = predicted;
  std::vector<cv::Point2f> back;
  std::vector<unsigned char> forward_ok;
  std::vector<unsigned char> back_ok;
  std::vector<float> errors;
  const cv::Size window(options.tracking_window_px, options.tracking_window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(warped, current, predicted, tracked, forward_ok, errors, window, levels,
                           criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  cv::calcOpticalFlowPyrLK(current, warped, tracked, back, back_ok, errors, window, levels,
                           criteria);
  const double max_miss_squared = options.max_forward_backward_px * options.max_forward_backward_px;
  int live = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const cv::Point2f miss = back[i] - predicted[i];
    const cv::Point2f& p = tracked[i];
    alive[i] = forward_ok[i] && back_ok[i] && miss.dot(miss) <= max_miss_squared && p.x >= 0.0f &&
               p.y >= 0.0f && p.x <= static_cast<float>(current.cols - 1) &&
               p.y <= static_cast<float>(current.rows - 1);
    points[i] = p;
    live += alive[i];
  }
  return live;
}

// The zero-mean normalised correlation of two images of one size over `mask`'s non-zero pixels.
double masked_correlation(const cv::Mat& first, const cv::Mat& second, const cv::Mat& mask) {
  cv::Mat first_float;
  cv::Mat second_float;
  first.convertTo(first_float, CV_32F);
  second.convertTo(second_float, CV_32F);
  cv::Scalar first_mean;
  cv::Scalar first_sd;
  cv::Scalar second_mean;
  cv::Scalar second_sd;
  cv::meanStdDev(first_float, first_mean, first_sd, mask);
  cv::meanStdDev(second_float, second_mean, second_sd, mask);
  if (first_sd[0] <= 0.0 || second_sd[0] <= 0.0) return 0.0;
  const double product_mean = cv::mean(first_float.mul(second_float), mask)[0];
  return (product_mean - first_mean[0] * second_mean[0]) / (first_sd[0] * second_sd[0]);
}

// Step 1b's second seed (RoadPlaneMotionOptions::max_seed_travel_over_height): the road's
// homography for straight travel s along the car's forward direction f over the road (unit normal
// n, pointing down, at the camera's height h), X2 = X1 - s f and n^T X1 = h, so
// H = I - (s / h) f n^T, with f and n from the guide (else the optical axis and +y) and s / h
// searched on a grid 5 % apart: the oldest image warped by each and compared with the current one
// over the road region, both at half resolution. Empty when the search is off or nothing
// correlates.
cv::Mat searched_road_homography(const cv::Mat& oldest, const cv::Mat& current,
                                 const cv::Mat& road_mask, const core::CameraIntrinsics& intrinsics,
                                 const RoadPlaneMotionOptions& options,
                                 const std::optional<SequenceGuide>& guide) {
  const double first = std::max(options.min_translation_over_height, 0.05);
  if (options.max_seed_travel_over_height <= first) return {};
  Eigen::Vector3d forward = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d down = Eigen::Vector3d::UnitY();
  if (guide) {
    const std::optional<Eigen::Matrix3d> vehicle_from_camera = vehicle_from_camera_rotation(
        guide->vanishing_point_px, guide->horizon_line, intrinsics.camera_matrix());
    if (vehicle_from_camera) {
      const Eigen::Matrix3d optical_from_vehicle =
          (*vehicle_from_camera * body_from_optical()).transpose();
      forward = optical_from_vehicle.col(0);
      down = -optical_from_vehicle.col(2);
    }
  }
  cv::Mat oldest_half;
  cv::Mat current_half;
  cv::Mat mask_half;
  cv::pyrDown(oldest, oldest_half);
  cv::pyrDown(current, current_half);
  cv::resize(road_mask, mask_half, current_half.size(), 0.0, 0.0, cv::INTER_NEAREST);
  const cv::Rect box = cv::boundingRect(mask_half);
  if (box.area() == 0) return {};
  const cv::Mat current_box = current_half(box);
  const cv::Mat mask_box = mask_half(box);
  // Pixel (u, v) of the half image is (2u, 2v) of the whole one.
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  Eigen::Matrix3d half_from_full = Eigen::Matrix3d::Identity();
  half_from_full(0, 0) = half_from_full(1, 1) = 0.5;
  Eigen::Matrix3d box_from_half = Eigen::Matrix3d::Identity();
  box_from_half(0, 2) = -box.x;
  box_from_half(1, 2) = -box.y;
  const auto pixel_homography = [&](double travel_over_height) {
    const Eigen::Matrix3d plane =
        Eigen::Matrix3d::Identity() - travel_over_height * forward * down.transpose();
    return Eigen::Matrix3d(camera_matrix * plane * camera_matrix.inverse());
  };
  const auto to_cv = [](const Eigen::Matrix3d& matrix) {
    cv::Mat out(3, 3, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out.at<double>(r, c) = matrix(r, c);
    }
    return out;
  };
  const double step = std::log(1.05);
  const int candidates = static_cast<int>(
      std::floor(std::log(options.max_seed_travel_over_height / first) / step)) + 1;
  std::vector<double> scores(static_cast<std::size_t>(candidates), -1.0);
  cv::Mat warped;
  for (int k = 0; k < candidates; ++k) {
    const Eigen::Matrix3d in_box =
        box_from_half * half_from_full * pixel_homography(first * std::exp(k * step)) *
        half_from_full.inverse();
    cv::warpPerspective(oldest_half, warped, to_cv(in_box), box.size(), cv::INTER_LINEAR,
                        cv::BORDER_REPLICATE);
    scores[static_cast<std::size_t>(k)] = masked_correlation(warped, current_box, mask_box);
  }
  const auto best = std::max_element(scores.begin(), scores.end());
  if (*best <= 0.0) return {};
  const auto k = static_cast<double>(best - scores.begin());
  // The parabola through the best and its neighbours, in the logarithm of s / h.
  double offset = 0.0;
  if (best != scores.begin() && best + 1 != scores.end()) {
    const double left = *(best - 1);
    const double right = *(best + 1);
    const double curvature = left - 2.0 * *best + right;
    if (curvature < 0.0) offset = std::clamp(0.5 * (left - right) / curvature, -0.5, 0.5);
  }
  return to_cv(pixel_homography(first * std::exp((k + offset) * step)));
}

// The road region of step 1: below the row of `road_region_depression`, inside the wedge of
// `max_lateral_over_height`.
cv::Mat road_region_mask(const cv::Size& size, const core::CameraIntrinsics& intrinsics,
                         const RoadPlaneMotionOptions& options) {
  const double top_row = intrinsics.cy + intrinsics.fy * std::tan(options.road_region_depression);
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
RoadTracks track_road_points(const std::vector<cv::Mat>& greys, const cv::Mat& road_mask,
                             const RoadPlaneMotionOptions& options) {
  const cv::Mat& oldest = greys.front();
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(oldest, corners, options.max_features, options.feature_quality,
                          options.min_feature_distance_px, road_mask);
  if (corners.empty()) return {};
  std::vector<cv::Point2f> points = corners;
  std::vector<unsigned char> alive(points.size(), 1);
  for (std::size_t k = 1; k < greys.size(); ++k) {
    track_step(greys[k - 1], greys[k], options, points, alive);
  }
  if (options.prewarp) {
    const cv::Mat homography = homography_of_live_tracks(options, corners, points, alive);
    if (!homography.empty()) {
      retrack_through_homography(oldest, greys.back(), options, homography, 1, corners, points,
                                 alive);
    }
  }
  return live_tracks(corners, points, alive);
}

// Step 1 from the searched seed (RoadPlaneMotionOptions::max_seed_travel_over_height): corners
// down to `seeded_feature_quality`, tracked from where the searched homography puts them through
// two pyramid levels (the guide's directions are a few tenths of a degree off, the nominal ones a
// few degrees), then once more through the homography of those tracks, as step 1b. Empty when the
// search finds nothing.
RoadTracks track_from_searched_seed(const cv::Mat& oldest, const cv::Mat& current,
                                    const cv::Mat& road_mask,
                                    const core::CameraIntrinsics& intrinsics,
                                    const RoadPlaneMotionOptions& options,
                                    const std::optional<SequenceGuide>& guide) {
  const cv::Mat searched =
      searched_road_homography(oldest, current, road_mask, intrinsics, options, guide);
  if (searched.empty()) return {};
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(oldest, corners, options.max_features, options.seeded_feature_quality,
                          options.min_feature_distance_px, road_mask);
  if (corners.empty()) return {};
  std::vector<cv::Point2f> points(corners.size());
  std::vector<unsigned char> alive(corners.size(), 0);
  retrack_through_homography(oldest, current, options, searched, 2, corners, points, alive);
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
    best = PlaneMotion{from_cv(rotations[i]), vector_from_cv(translations[i]), normal};
  }
  if (!best || std::acos(std::clamp(best->normal.y(), -1.0, 1.0)) > options.max_normal_tilt) {
    return std::nullopt;
  }
  return best;
}

}  // namespace

FrameEstimate road_plane_from_tracks(const std::vector<Eigen::Vector2d>& previous_px,
                                     const std::vector<Eigen::Vector2d>& current_px,
                                     const core::CameraIntrinsics& intrinsics,
                                     const RoadPlaneMotionOptions& options) {
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
  const Eigen::Vector3d forward = motion->rotation * (half_turn * chord.normalized());
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
  estimate.quality = static_cast<double>(inliers) / static_cast<double>(count);
  // RMS transfer error of the inliers [rad at the image centre, like the geometric residual].
  const Eigen::Matrix3d h = from_cv(homography);
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
  return estimate;
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

// Steps 1-5, from the tracked seed and, when that gives no road plane (other than for too little
// motion), from the searched one; `used` receives the tracks of the estimate returned.
FrameEstimate fit_road_plane(const std::vector<cv::Mat>& greys,
                             const core::CameraIntrinsics& intrinsics,
                             const RoadPlaneMotionOptions& options,
                             const std::optional<SequenceGuide>& guide, RoadTracks& used) {
  const cv::Mat mask = road_region_mask(greys.front().size(), intrinsics, options);
  used = track_road_points(greys, mask, options);
  FrameEstimate estimate =
      road_plane_from_tracks(used.oldest_px, used.current_px, intrinsics, options);
  if (estimate.usable() || !options.prewarp || options.max_seed_travel_over_height <= 0.0 ||
      estimate.rejection == FrameRejection::kTooLittleMotion) {
    return estimate;
  }
  RoadTracks searched =
      track_from_searched_seed(greys.front(), greys.back(), mask, intrinsics, options, guide);
  FrameEstimate from_search =
      road_plane_from_tracks(searched.oldest_px, searched.current_px, intrinsics, options);
  if (!from_search.usable()) return estimate;
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
