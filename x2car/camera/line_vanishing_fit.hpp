// Vanishing points from line segments, shared by the geometric estimator (its RANSAC's inliers
// refined, steps 3-4 of docs/methods.md camera §1) and the learned one (the network's vanishing
// point refined on the segments it says pass through it, §1b): each segment spans a plane with the
// camera centre, and a direction through all those planes is the smallest eigenvector of their
// normals' weighted scatter.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::camera {

// One line segment in undistorted pixels, and the plane it spans with the camera centre.
struct ImageSegment {
  Eigen::Vector2d midpoint_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // unit, in the image
  Eigen::Vector3d line = Eigen::Vector3d::UnitY();       // a u + b v + c = 0, a^2 + b^2 = 1
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();     // unit normal of the plane, optical frame
  double length_px = 0.0;
};

// The segment from `start_px` to `end_px` (distinct points) of a camera whose matrix K is given
// transposed: the plane of the rays K^-1 p for p on the line has the normal K^T l.
ImageSegment image_segment(const Eigen::Vector2d& start_px, const Eigen::Vector2d& end_px,
                           const Eigen::Matrix3d& camera_matrix_transposed);

// |sin| of the angle between the segment and the line from its midpoint to the (homogeneous)
// image point `vanishing`; the same for a vanishing point at infinity.
double misalignment(const ImageSegment& segment, const Eigen::Vector3d& vanishing);

// A direction in the optical frame and the segments through its vanishing point.
struct DirectionFit {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit, optical frame
  std::vector<int> inliers;                              // indices into the segments
  double support_px = 0.0;                               // summed length of the inliers
};

// The `candidates` (indices into `segments`) within `max_sin` (misalignment) of `direction`.
DirectionFit inliers_of(const std::vector<ImageSegment>& segments,
                        const std::vector<int>& candidates, const Eigen::Matrix3d& camera_matrix,
                        const Eigen::Vector3d& direction, double max_sin);

// `rounds` times: the weighted least-squares direction of fit's inliers, then the candidates
// within `max_sin` of it as the inliers. A line fitted to L pixels with unit noise has its offset
// known to 1/L and its slope to sqrt(12 / L^3) (continuous least squares), so at distance D from
// its midpoint its position varies as (L^2 + 12 D^2) / L^3: the weights are the inverse. Stops
// early at fewer than 2 inliers or at a direction `admissible` refuses (the fit before it kept).
DirectionFit refine_direction(const std::vector<ImageSegment>& segments,
                              const std::vector<int>& candidates,
                              const Eigen::Matrix3d& camera_matrix, double max_sin, int rounds,
                              DirectionFit fit,
                              const std::function<bool(const Eigen::Vector3d&)>& admissible);

// How a guessed vanishing point is refined on segments said to pass through it.
struct VanishingRefinementOptions {
  // The segments within this angle of the guess are the first inliers: about the guess's own
  // error seen from a segment a few hundred pixels away [rad].
  double capture_angle = rad_from_deg(4.0);
  // Then least-squares rounds, each keeping the segments within this angle of the last fit [rad].
  double inlier_angle = rad_from_deg(1.0);
  int rounds = 3;
  // Fewer inliers than this at any round: no refinement.
  int min_inliers = 4;
  // A fit further than this from the guess is refused [rad]: the segments said something else.
  double max_shift = rad_from_deg(5.0);

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The direction (unit, optical frame, z > 0) of `guess`'s vanishing point refined on `segments`,
// or nullopt when they do not carry it (too few inliers, a fit too far from the guess).
std::optional<DirectionFit> refine_vanishing_guess(const std::vector<ImageSegment>& segments,
                                                   const Eigen::Matrix3d& camera_matrix,
                                                   const Eigen::Vector3d& guess,
                                                   const VanishingRefinementOptions& options);

}  // namespace x2car::camera
