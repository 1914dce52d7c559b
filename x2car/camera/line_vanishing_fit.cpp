#include "x2car/camera/line_vanishing_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "x2car/core/options_check.hpp"

namespace x2car::camera {

ImageSegment image_segment(const Eigen::Vector2d& start_px, const Eigen::Vector2d& end_px,
                           const Eigen::Matrix3d& camera_matrix_transposed) {
  ImageSegment segment;
  segment.length_px = (end_px - start_px).norm();
  segment.midpoint_px = 0.5 * (start_px + end_px);
  segment.direction = (end_px - start_px) / segment.length_px;
  segment.line = start_px.homogeneous().cross(end_px.homogeneous());
  segment.line /= segment.line.head<2>().norm();
  segment.normal = (camera_matrix_transposed * segment.line).normalized();
  return segment;
}

double misalignment(const ImageSegment& segment, const Eigen::Vector3d& vanishing) {
  const Eigen::Vector3d through = segment.midpoint_px.homogeneous().cross(vanishing);
  const double norm = through.head<2>().norm();
  if (norm == 0.0) return 0.0;  // the vanishing point is the midpoint: any direction fits
  return std::abs(through.x() * segment.line.y() - through.y() * segment.line.x()) / norm;
}

DirectionFit inliers_of(const std::vector<ImageSegment>& segments,
                        const std::vector<int>& candidates, const Eigen::Matrix3d& camera_matrix,
                        const Eigen::Vector3d& direction, double max_sin) {
  DirectionFit fit;
  fit.direction = direction;
  const Eigen::Vector3d vanishing = camera_matrix * direction;
  for (const int index : candidates) {
    const ImageSegment& segment = segments[static_cast<std::size_t>(index)];
    if (misalignment(segment, vanishing) < max_sin) {
      fit.inliers.push_back(index);
      fit.support_px += segment.length_px;
    }
  }
  return fit;
}

DirectionFit refine_direction(const std::vector<ImageSegment>& segments,
                              const std::vector<int>& candidates,
                              const Eigen::Matrix3d& camera_matrix, double max_sin, int rounds,
                              DirectionFit fit,
                              const std::function<bool(const Eigen::Vector3d&)>& admissible) {
  for (int round = 0; round < rounds && fit.inliers.size() >= 2; ++round) {
    const Eigen::Vector3d vanishing = camera_matrix * fit.direction;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const int index : fit.inliers) {
      const ImageSegment& segment = segments[static_cast<std::size_t>(index)];
      // Far away (a vanishing point near infinity) every segment is as far: D only scales.
      const double distance_px =
          std::abs(vanishing.z()) > 1e-9 * vanishing.head<2>().norm()
              ? std::min((vanishing.head<2>() / vanishing.z() - segment.midpoint_px).norm(), 1e6)
              : 1e6;
      const double length = segment.length_px;
      const double weight =
          length * length * length / (length * length + 12.0 * distance_px * distance_px);
      scatter += weight * segment.normal * segment.normal.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    Eigen::Vector3d direction = solver.eigenvectors().col(0);
    if (direction.dot(fit.direction) < 0.0) direction = -direction;
    if (!admissible(direction)) break;
    fit = inliers_of(segments, candidates, camera_matrix, direction, max_sin);
  }
  return fit;
}

void VanishingRefinementOptions::Check() const {
  const OptionsCheck check("VanishingRefinementOptions");
  check.in_range("capture_angle", capture_angle, 0.0, kPi / 4.0, Bounds::kOpenMin);
  check.in_range("inlier_angle", inlier_angle, 0.0, kPi / 4.0, Bounds::kOpenMin);
  check.at_least("rounds", rounds, 1);
  check.at_least("min_inliers", min_inliers, 2);
  check.in_range("max_shift", max_shift, 0.0, kPi / 2.0, Bounds::kOpenMin);
}

std::optional<DirectionFit> refine_vanishing_guess(const std::vector<ImageSegment>& segments,
                                                   const Eigen::Matrix3d& camera_matrix,
                                                   const Eigen::Vector3d& guess,
                                                   const VanishingRefinementOptions& options) {
  const Eigen::Vector3d start = guess.normalized();
  if (!start.allFinite() || start.z() <= 0.0) return std::nullopt;
  std::vector<int> candidates(segments.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  const auto min_inliers = static_cast<std::size_t>(options.min_inliers);
  DirectionFit fit =
      inliers_of(segments, candidates, camera_matrix, start, std::sin(options.capture_angle));
  if (fit.inliers.size() < min_inliers) return std::nullopt;
  const double min_cos = std::cos(options.max_shift);
  bool refused = false;
  const auto near_guess = [&](const Eigen::Vector3d& direction) {
    refused = direction.dot(start) < min_cos;
    return !refused;
  };
  fit = refine_direction(segments, candidates, camera_matrix, std::sin(options.inlier_angle),
                         options.rounds, std::move(fit), near_guess);
  if (refused || fit.inliers.size() < min_inliers) return std::nullopt;
  return fit;
}

}  // namespace x2car::camera
