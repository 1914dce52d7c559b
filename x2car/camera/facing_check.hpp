// Whether a camera looks along the car's travel or against it, from the images' motion.
//
// The vanishing-point methods (paper §III-A, eq:camera_R3) read the car's x axis as the ray to the
// road's vanishing point, which is the same point of the image for a camera that looks ahead and
// for one that looks back: a rear camera would come back with its yaw 180 deg wrong. The motion
// tells them apart. Driving ahead, the scene flows out of the vanishing point of the travel (the
// focus of expansion) in a camera that looks ahead, and into it (the focus of contraction) in one
// that looks back. Per pair of consecutive frames, corners are tracked (pyramidal LK, both ways)
// and the median of their displacements along the rays from the vanishing point decides the pair;
// the pairs vote.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

struct FacingCheckOptions {
  // Pairs of consecutive frames sampled evenly from those offered.
  int frame_pairs = 24;
  // Corners tracked per pair (cv::goodFeaturesToTrack).
  int corners_per_pair = 200;
  // A pair's median displacement along the rays from the vanishing point, out of it (+) or into it
  // (-), must reach this to count as moving [px]; smaller pairs (a car standing) do not vote.
  double min_radial_flow_px = 0.25;
  // Corners that moved less than this between the two frames are left out of the median [px]:
  // the car's own body, a reflection, a logo stay put (a pair needs 8 that moved).
  double min_corner_motion_px = 0.1;
  // Corners nearer the vanishing point than this share of the image's width are left out: the ray
  // from it is ill-defined there and the flow small [-].
  double min_distance_from_vanishing_point = 0.05;
  // Moving pairs needed to decide, and the share of them that must agree.
  int min_moving_pairs = 4;
  double min_agreement = 0.75;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

enum class Facing {
  kAhead,        // the scene flows out of the vanishing point
  kBack,         // into it
  kUndecided,    // too few pairs moved (a car standing, a scene without texture)
  kConflicting,  // the moving pairs disagree
};

struct FacingCheck {
  Facing facing = Facing::kUndecided;
  std::size_t pairs = 0;        // pairs looked at
  std::size_t expanding = 0;    // moving pairs that flowed out of the vanishing point
  std::size_t contracting = 0;  // into it
};

// `read(i)` gives frame i (8-bit grey or BGR, the intrinsics' size); `pairs` are (earlier, later)
// frame indices, sorted, sampled evenly down to options.frame_pairs and read in order (a video
// decodes forward once); `vanishing_point_px` is that of the car's x axis as the
// calibration found it [undistorted px]; `ignored_region` (nonzero: left out) may be empty. A pair
// with an empty image (one that did not decode) does not vote; InputError from `read` passes
// through.
FacingCheck check_facing(const std::function<cv::Mat(std::size_t)>& read,
                         const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                         const core::CameraIntrinsics& intrinsics,
                         const Eigen::Vector2d& vanishing_point_px, const cv::Mat& ignored_region,
                         const FacingCheckOptions& options = {});

}  // namespace x2car::camera
