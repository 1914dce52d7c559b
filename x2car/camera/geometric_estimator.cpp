#include "x2car/camera/geometric_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <utility>
#include <vector>

#include "x2car/camera/grey_image.hpp"
#include "x2car/camera/line_vanishing_fit.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void GeometricEstimatorOptions::Check() const {
  const OptionsCheck check("GeometricEstimatorOptions");
  check.that(ignored_region.empty() || ignored_region.type() == CV_8UC1, "ignored_region",
             "must be an 8-bit single-channel image");
  check.in_range("lsd_scale", lsd_scale, 0.0, 1.0, Bounds::kOpenMin);
  check.non_negative("min_segment_length_px", min_segment_length_px);
  check.at_least("min_segments", min_segments, 2);
  check.at_least("ransac_iterations", ransac_iterations, 1);
  check.in_range("inlier_angle", inlier_angle, 0.0, kPi / 4.0, Bounds::kOpenMin);
  check.at_least("min_road_inliers", min_road_inliers, 2);
  check.in_range("road_cone", road_cone, 0.0, kPi / 2.0, Bounds::kOpen);
  check.in_range("max_vertical_tilt", max_vertical_tilt, 0.0, kPi / 2.0, Bounds::kOpen);
  check.in_range("vertical_cone", vertical_cone, 0.0, kPi / 2.0, Bounds::kOpen);
  check.at_least("min_horizon_inliers", min_horizon_inliers, 2);
  check.in_range("second_horizontal_max_skew", second_horizontal_max_skew, 0.0, kPi / 2.0,
                 Bounds::kOpen);
  check.at_least("refine_rounds", refine_rounds, 0);
}

namespace {

// Whether pixel `point` lies in `region` (8-bit, the image's size; empty: nowhere). A segment's
// end may lie a fraction of a pixel outside the image: it reads the nearest pixel.
bool in_region(const cv::Mat& region, const Eigen::Vector2d& point) {
  if (region.empty()) return false;
  const int column = std::clamp(static_cast<int>(std::lround(point.x())), 0, region.cols - 1);
  const int row = std::clamp(static_cast<int>(std::lround(point.y())), 0, region.rows - 1);
  return region.at<unsigned char>(row, column) != 0;
}

// Step 1-2: LSD (ignored_region's segments dropped), undistorted endpoints, the length filter, each
// segment's plane.
std::vector<ImageSegment> detect_segments(const cv::Mat& grey,
                                          const core::CameraIntrinsics& intrinsics,
                                          const GeometricEstimatorOptions& options) {
  const cv::Ptr<cv::LineSegmentDetector> detector =
      cv::createLineSegmentDetector(cv::LSD_REFINE_STD, options.lsd_scale);
  std::vector<cv::Vec4f> lines;
  detector->detect(grey, lines);
  const Eigen::Matrix3d camera_matrix_transposed = intrinsics.camera_matrix().transpose();
  const bool distorted = intrinsics.distortion_model != core::DistortionModel::kNone;
  std::vector<ImageSegment> segments;
  segments.reserve(lines.size());
  for (const cv::Vec4f& line : lines) {
    Eigen::Vector2d start(line[0], line[1]);
    Eigen::Vector2d end(line[2], line[3]);
    if (in_region(options.ignored_region, start) || in_region(options.ignored_region, end) ||
        in_region(options.ignored_region, 0.5 * (start + end))) {
      continue;
    }
    if (distorted) {
      start = core::undistort_pixel(intrinsics, start);
      end = core::undistort_pixel(intrinsics, end);
    }
    const double length = (end - start).norm();
    if (!(length >= options.min_segment_length_px) || length == 0.0) continue;
    segments.push_back(image_segment(start, end, camera_matrix_transposed));
  }
  return segments;
}

// The summed length of the candidates that support `direction` (RANSAC's score; no allocation).
double support_of(const std::vector<ImageSegment>& segments, const std::vector<int>& candidates,
                  const Eigen::Vector3d& vanishing, double max_sin) {
  double support_px = 0.0;
  for (const int index : candidates) {
    const ImageSegment& segment = segments[static_cast<std::size_t>(index)];
    if (misalignment(segment, vanishing) < max_sin) support_px += segment.length_px;
  }
  return support_px;
}

// Step 3: the direction most of the candidates' length agrees on, among the admissible ones.
template <typename Admissible>
std::optional<DirectionFit> ransac_direction(const std::vector<ImageSegment>& segments,
                                             const std::vector<int>& candidates,
                                             const Eigen::Matrix3d& camera_matrix,
                                             const GeometricEstimatorOptions& options,
                                             const Admissible& admissible) {
  if (candidates.size() < 2) return std::nullopt;
  std::mt19937_64 random(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  const double max_sin = std::sin(options.inlier_angle);
  std::optional<Eigen::Vector3d> best;
  double best_support_px = 0.0;
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    const std::size_t first = pick(random);
    const std::size_t second = pick(random);
    if (first == second) continue;
    Eigen::Vector3d direction = segments[static_cast<std::size_t>(candidates[first])].normal.cross(
        segments[static_cast<std::size_t>(candidates[second])].normal);
    const double norm = direction.norm();
    if (norm < 1e-9) continue;
    direction /= norm;
    if (!admissible(direction)) {
      direction = -direction;
      if (!admissible(direction)) continue;
    }
    const double support_px = support_of(segments, candidates, camera_matrix * direction, max_sin);
    if (!best || support_px > best_support_px) {
      best = direction;
      best_support_px = support_px;
    }
  }
  if (!best) return std::nullopt;
  return inliers_of(segments, candidates, camera_matrix, *best, max_sin);
}

// Step 4: weighted least squares on the inliers, then the inliers again; `refine_rounds` times.
DirectionFit refine_road_or_horizon(const std::vector<ImageSegment>& segments,
                                    const std::vector<int>& candidates,
                                    const Eigen::Matrix3d& camera_matrix,
                                    const GeometricEstimatorOptions& options, DirectionFit fit,
                                    const std::function<bool(const Eigen::Vector3d&)>& admissible) {
  return refine_direction(segments, candidates, camera_matrix, std::sin(options.inlier_angle),
                          options.refine_rounds, std::move(fit), admissible);
}

double rms_angle(const std::vector<ImageSegment>& segments, const DirectionFit& fit,
                 const Eigen::Matrix3d& camera_matrix) {
  if (fit.inliers.empty()) return 0.0;
  const Eigen::Vector3d vanishing = camera_matrix * fit.direction;
  double sum = 0.0;
  for (const int index : fit.inliers) {
    const double angle = std::asin(
        std::min(1.0, misalignment(segments[static_cast<std::size_t>(index)], vanishing)));
    sum += angle * angle;
  }
  return std::sqrt(sum / static_cast<double>(fit.inliers.size()));
}

std::vector<int> all_but(std::size_t count, const std::vector<int>& excluded) {
  std::vector<char> skip(count, 0);
  for (const int index : excluded) skip[static_cast<std::size_t>(index)] = 1;
  std::vector<int> rest;
  rest.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (!skip[i]) rest.push_back(static_cast<int>(i));
  }
  return rest;
}

struct HorizonFit {
  Eigen::Vector3d up_in_optical;
  DirectionFit fit;
  HorizonSource source = HorizonSource::kNone;
};

// Step 5: the up direction from the vertical vanishing point, else from a second horizontal one.
std::optional<HorizonFit> fit_horizon(const std::vector<ImageSegment>& segments,
                                      const std::vector<int>& road_inliers,
                                      const Eigen::Vector3d& road_direction,
                                      const Eigen::Matrix3d& camera_matrix,
                                      const GeometricEstimatorOptions& options) {
  const std::vector<int> rest = all_but(segments.size(), road_inliers);
  const double max_tilt_sin = std::sin(options.max_vertical_tilt);
  std::vector<int> upright;
  std::vector<int> other;
  for (const int index : rest) {
    const bool is_upright =
        std::abs(segments[static_cast<std::size_t>(index)].direction.x()) < max_tilt_sin;
    (is_upright ? upright : other).push_back(index);
  }
  const auto min_inliers = static_cast<std::size_t>(options.min_horizon_inliers);

  const double vertical_cos = std::cos(options.vertical_cone);
  const auto vertical = [&](const Eigen::Vector3d& d) { return std::abs(d.y()) >= vertical_cos; };
  if (std::optional<DirectionFit> fit =
          ransac_direction(segments, upright, camera_matrix, options, vertical);
      fit && fit->inliers.size() >= min_inliers) {
    DirectionFit refined = refine_road_or_horizon(segments, upright, camera_matrix, options,
                                                  std::move(*fit), vertical);
    if (refined.inliers.size() >= min_inliers) {
      Eigen::Vector3d up = refined.direction;
      if (up.y() > 0.0) up = -up;
      return HorizonFit{up, std::move(refined), HorizonSource::kVerticalVanishingPoint};
    }
  }

  // Horizontal (within 30 deg of the optical frame's x-z plane) and nearly perpendicular to the
  // road.
  const double max_skew_sin = std::sin(options.second_horizontal_max_skew);
  const auto across = [&](const Eigen::Vector3d& d) {
    return std::abs(d.dot(road_direction)) <= max_skew_sin && std::abs(d.y()) <= 0.5;
  };
  if (std::optional<DirectionFit> fit =
          ransac_direction(segments, other, camera_matrix, options, across);
      fit && fit->inliers.size() >= min_inliers) {
    DirectionFit refined =
        refine_road_or_horizon(segments, other, camera_matrix, options, std::move(*fit), across);
    if (refined.inliers.size() >= min_inliers) {
      Eigen::Vector3d up = road_direction.cross(refined.direction).normalized();
      if (up.y() > 0.0) up = -up;
      return HorizonFit{up, std::move(refined), HorizonSource::kSecondHorizontal};
    }
  }
  return std::nullopt;
}

// Every segment as a FrameLine, those of `fit` (when given) marked with `role`.
void describe_lines(const std::vector<ImageSegment>& segments, const DirectionFit* road,
                    const DirectionFit* horizon, std::vector<FrameLine>& lines) {
  lines.clear();
  lines.reserve(segments.size());
  for (const ImageSegment& segment : segments) {
    const Eigen::Vector2d half = 0.5 * segment.length_px * segment.direction;
    lines.push_back({segment.midpoint_px - half, segment.midpoint_px + half, LineRole::kOther});
  }
  for (const auto& [fit, role] :
       {std::pair{road, LineRole::kRoad}, std::pair{horizon, LineRole::kHorizon}}) {
    if (fit == nullptr) continue;
    for (const int index : fit->inliers) lines[static_cast<std::size_t>(index)].role = role;
  }
}

}  // namespace

FrameEstimate estimate_frame_geometric(const cv::Mat& image,
                                       const core::CameraIntrinsics& intrinsics,
                                       const GeometricEstimatorOptions& options,
                                       std::vector<FrameLine>* lines) {
  if (image.empty()) return rejected_frame(FrameRejection::kUnreadableImage);
  if (image.cols != intrinsics.width || image.rows != intrinsics.height ||
      (!options.ignored_region.empty() && options.ignored_region.size() != image.size())) {
    return rejected_frame(FrameRejection::kWrongImageSize);
  }
  const cv::Mat grey = grey_8bit(image);
  const std::vector<ImageSegment> segments = detect_segments(grey, intrinsics, options);
  if (lines != nullptr) describe_lines(segments, nullptr, nullptr, *lines);
  FrameEstimate estimate;
  estimate.segments = static_cast<int>(segments.size());
  if (segments.size() < static_cast<std::size_t>(options.min_segments)) {
    estimate.rejection = FrameRejection::kTooFewLines;
    return estimate;
  }
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  const std::vector<int> everything = all_but(segments.size(), {});

  // Steps 3-4: the road's vanishing point, ahead of the camera.
  const double cone_cos = std::cos(options.road_cone);
  const auto ahead = [&](const Eigen::Vector3d& d) { return d.z() >= cone_cos; };
  const auto min_inliers = static_cast<std::size_t>(options.min_road_inliers);
  std::optional<DirectionFit> road =
      ransac_direction(segments, everything, camera_matrix, options, ahead);
  if (road && road->inliers.size() >= min_inliers) {
    road = refine_road_or_horizon(segments, everything, camera_matrix, options, std::move(*road),
                                  ahead);
  }
  if (!road || road->inliers.size() < min_inliers) {
    // Tell a vanishing point elsewhere (a turn, a wall filling the view) from no agreement at all.
    const auto anywhere = [](const Eigen::Vector3d& d) { return d.z() > 0.0; };
    const std::optional<DirectionFit> elsewhere =
        ransac_direction(segments, everything, camera_matrix, options, anywhere);
    estimate.rejection = elsewhere && elsewhere->inliers.size() >= min_inliers
                             ? FrameRejection::kOutsideCone
                             : FrameRejection::kNoConsensus;
    return estimate;
  }
  if (lines != nullptr) describe_lines(segments, &*road, nullptr, *lines);
  estimate.road_inliers = static_cast<int>(road->inliers.size());
  estimate.road_residual_rms = rms_angle(segments, *road, camera_matrix);
  const Eigen::Vector3d road_image = camera_matrix * road->direction;
  estimate.road_vanishing_point_px = road_image.head<2>() / road_image.z();

  // Step 5: the horizon.
  const std::optional<HorizonFit> horizon =
      fit_horizon(segments, road->inliers, road->direction, camera_matrix, options);
  std::optional<Eigen::Vector3d> line;
  if (horizon) line = horizon_from_up(horizon->up_in_optical, camera_matrix);
  if (!line) {
    estimate.rejection = FrameRejection::kNoHorizon;
    return estimate;
  }
  if (lines != nullptr) describe_lines(segments, &*road, &horizon->fit, *lines);
  estimate.horizon_line = *line;
  estimate.horizon_source = horizon->source;
  estimate.horizon_inliers = static_cast<int>(horizon->fit.inliers.size());
  double total_px = 0.0;
  for (const ImageSegment& segment : segments) total_px += segment.length_px;
  estimate.quality = (road->support_px + horizon->fit.support_px) / total_px;
  return estimate;
}

FrameEstimator make_geometric_estimator(const GeometricEstimatorOptions& options) {
  options.Check();
  return [options](const cv::Mat& image, const core::CameraIntrinsics& intrinsics) {
    return estimate_frame_geometric(image, intrinsics, options);
  };
}

}  // namespace x2car::camera
