// The geometric per-frame estimator (DESIGN §2, issue 14 item 2): line segments -> the road's
// vanishing point -> the horizon, with no learning.
//
//   1. Line segments by LSD (von Gioi et al. 2012; OpenCV's createLineSegmentDetector, the
//      detector whose segments the paper's network also takes as queries, §III-A "Detection
//      Network"). Their endpoints are undistorted through the camera model, so every later step is
//      a pinhole's; segments shorter than min_segment_length_px are dropped.
//   2. Each segment and the camera centre span a plane with unit normal n = K^T l / |K^T l| (l the
//      segment's line): the rays of all the points it images. Parallel 3-D lines meet in the
//      direction d with n . d = 0 for all of them.
//   3. The road's vanishing point: RANSAC over pairs of segments (d = n_i x n_j), seeded, so the
//      same image always gives the same answer. A segment supports d when it points at d's image
//      to within inlier_angle (measured in the image at the segment, so a far vanishing point is
//      judged like a near one); a hypothesis scores the summed length of its supporters. Only
//      directions inside road_cone around the optical axis are hypotheses: the road lies ahead.
//   4. Least squares on the inliers: d minimises sum_i w_i (n_i . d)^2, the smallest eigenvector
//      of sum_i w_i n_i n_i^T, weights w_i = L_i^3 / (L_i^2 + 12 D_i^2) (L the segment's length, D
//      its distance to the vanishing point in pixels: the inverse variance, at the vanishing point,
//      of a line fitted to L pixels). Inliers are chosen again and the fit repeated.
//   5. The horizon. First choice, the vertical vanishing point of building edges, poles and trunks
//      (steps 3-4 on the remaining segments that run within max_vertical_tilt of the image's
//      vertical, hypotheses within vertical_cone of the image's y axis): its ray is the up
//      direction u, and the horizon is its polar line K^-T u. Otherwise a second horizontal
//      vanishing point d2 (stop lines, kerbs of side streets, facade rows across the view; within
//      second_horizontal_max_skew of perpendicular to the road's direction): u = d x d2.
//   Frames without enough lines, consensus or a horizon are rejected with the reason
//   (frame_estimate.hpp).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "x2car/camera/frame_estimate.hpp"
#include "x2car/core/camera_model.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera {

struct GeometricEstimatorOptions {
  // LSD's own scale: the image is resampled by it before detection (OpenCV's default 0.8 trades
  // a little accuracy against noise and time).
  double lsd_scale = 0.8;
  // Shorter segments (after undistortion) are dropped: their direction is too uncertain [px].
  double min_segment_length_px = 15.0;
  // Fewer usable segments than this: too_few_lines.
  int min_segments = 8;
  // RANSAC hypotheses per vanishing point.
  int ransac_iterations = 400;
  // A segment supports a vanishing point when it points at it to within this angle [rad].
  double inlier_angle = rad_from_deg(1.0);
  // The road's vanishing point needs at least this many supporting segments: no_consensus.
  int min_road_inliers = 6;
  // The road's direction lies within this angle of the optical axis [rad]: mountings of +-5 deg
  // and curves of the road ahead stay well inside; a wall or a side street does not.
  double road_cone = rad_from_deg(20.0);
  // Candidate vertical segments run within this angle of the image's vertical [rad].
  double max_vertical_tilt = rad_from_deg(25.0);
  // The vertical vanishing point's ray lies within this angle of the optical frame's y axis [rad].
  double vertical_cone = rad_from_deg(20.0);
  // A horizon needs at least this many supporting segments.
  int min_horizon_inliers = 4;
  // The second horizontal direction is within this angle of perpendicular to the road's [rad].
  double second_horizontal_max_skew = rad_from_deg(10.0);
  // Least-squares rounds after RANSAC (each: fit, then choose the inliers again).
  int refine_rounds = 2;
  // Of the RANSAC sampling; every frame uses the same seed, so a frame's result does not depend on
  // which thread or in which order it ran.
  std::uint64_t seed = 1;
  // Pixels to leave out (8-bit, the images' size; nonzero: the car's own body, car_region.hpp): a
  // segment with an end or its middle there is dropped. Empty: none.
  cv::Mat ignored_region;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// What a usable segment supported, for drawing it (the report's frames).
enum class LineRole {
  kOther,    // neither vanishing point
  kRoad,     // the road's vanishing point
  kHorizon,  // the vertical (or second horizontal) vanishing point that gave the horizon
};

// A usable segment (after the length filter), in undistorted pixels.
struct FrameLine {
  Eigen::Vector2d start_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d end_px = Eigen::Vector2d::Zero();
  LineRole role = LineRole::kOther;
};

// The estimate of one image (grey or BGR, 8 or 16 bit). An image whose size differs from the
// intrinsics' (or from options.ignored_region's) is rejected (wrong_image_size), an empty one
// unreadable_image. Pure: safe to call from several threads at once. `lines`, when given,
// receives every usable segment and its role (as far as the estimate got before a rejection).
FrameEstimate estimate_frame_geometric(const cv::Mat& image,
                                       const core::CameraIntrinsics& intrinsics,
                                       const GeometricEstimatorOptions& options = {},
                                       std::vector<FrameLine>* lines = nullptr);

// The same behind the FrameEstimator interface. Checks the options once (std::invalid_argument).
FrameEstimator make_geometric_estimator(const GeometricEstimatorOptions& options = {});

}  // namespace x2car::camera
