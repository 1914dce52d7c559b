// What a per-frame estimator reports (DESIGN §2, issue 14 item 2): the vanishing point of the road
// direction and the horizon line of one image, or why the image gave neither. The geometric
// estimator (geometric_estimator.hpp), the motion one and the paper's network plug in behind the
// same FrameEstimator; the temporal filter and the calibrator see only FrameEstimate.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/camera_model.hpp"
#include "x2car/core/enum_names.hpp"

namespace cv {
class Mat;
}  // namespace cv

namespace x2car::camera {

// Why a frame gives no estimate; each is counted in the result's rejections under its name.
enum class FrameRejection {
  kTooFewLines,      // "too_few_lines": fewer usable line segments than the estimator needs
  kNoConsensus,      // "no_consensus": no vanishing point that enough segments agree on
  kOutsideCone,      // "outside_cone": the best vanishing point is outside the plausible cone
                     //   around the optical axis (the road is not ahead: a turn, a wall)
  kNoHorizon,        // "no_horizon": no vertical vanishing point and no second horizontal one
  kUnreadableImage,  // "unreadable_image": the image could not be decoded
  kWrongImageSize,   // "wrong_image_size": the image's size differs from the intrinsics'
  // The motion estimator's (road_plane_motion.hpp):
  kNoPreviousFrame,  // "no_previous_frame": the first frame, or one after a gap in time
  kTooFewTracks,     // "too_few_tracks": too few road points tracked into the frame
  kTooLittleMotion,  // "too_little_motion": the car moved too little for the road's parallax
  kNoRoadPlane,      // "no_road_plane": no plane below the camera that enough tracks agree on
};

constexpr std::array<EnumName<FrameRejection>, 10> kFrameRejectionNames{{
    {FrameRejection::kTooFewLines, "too_few_lines"},
    {FrameRejection::kNoConsensus, "no_consensus"},
    {FrameRejection::kOutsideCone, "outside_cone"},
    {FrameRejection::kNoHorizon, "no_horizon"},
    {FrameRejection::kUnreadableImage, "unreadable_image"},
    {FrameRejection::kWrongImageSize, "wrong_image_size"},
    {FrameRejection::kNoPreviousFrame, "no_previous_frame"},
    {FrameRejection::kTooFewTracks, "too_few_tracks"},
    {FrameRejection::kTooLittleMotion, "too_little_motion"},
    {FrameRejection::kNoRoadPlane, "no_road_plane"},
}};

inline const char* to_string(FrameRejection rejection) {
  return enum_to_string(kFrameRejectionNames, rejection);
}

// Where the horizon came from.
enum class HorizonSource {
  kNone,
  kVerticalVanishingPoint,  // the up direction is the ray to the vertical vanishing point
  kSecondHorizontal,        // the line through the road's and a second horizontal vanishing point
  kRoadPlaneMotion,         // the road plane's, from its motion between two frames
  kNetwork,                 // the learned network's (camera_net/learned_estimator.hpp)
};

// The motion estimator's: how the camera moved between the oldest frame of its pair and the
// current one (road_plane_motion.hpp). What the car did, seen from the images alone: the image
// motion gate of the temporal filter reads it when no GNSS/INS log gives the car's motion.
struct CameraPairMotion {
  // The camera's turn about the road's normal, left (counter-clockwise seen from above) positive:
  // the car's yaw over the pair [rad].
  double turn_about_up = 0.0;
  // The distance travelled over the camera's height above the road, |t| / d.
  double travel_over_height = 0.0;
};

struct FrameEstimate {
  // Set when the frame is unusable; the geometry below is then meaningless.
  std::optional<FrameRejection> rejection;

  // Vanishing point of the road's direction [undistorted px] (core::undistort_pixel): on a
  // straight road driven straight, the car's x axis.
  Eigen::Vector2d road_vanishing_point_px = Eigen::Vector2d::Zero();
  // Horizon line a u + b v + c = 0 in undistorted pixels, a^2 + b^2 = 1, b > 0.
  Eigen::Vector3d horizon_line = Eigen::Vector3d(0.0, 1.0, 0.0);
  HorizonSource horizon_source = HorizonSource::kNone;
  // auto: the road plane's horizon and the vanishing point of the car's travel between the two
  // frames, from the motion estimator when the frame pair gave them, beside the lines' vanishing
  // point and (gravity's) horizon above. Their roll is free of the road's crossfall and their
  // pitch of the grade changing ahead of the car, but each scatters by ~0.3 deg a frame, so they
  // are averaged over the steady windows rather than tested (temporal_filter.hpp).
  std::optional<Eigen::Vector3d> road_plane_horizon_line;
  std::optional<Eigen::Vector2d> road_plane_vanishing_point_px;  // [undistorted px]
  // The motion estimator's, and auto's beside the two above: the camera's motion over the pair.
  std::optional<CameraPairMotion> pair_motion;

  // How much of the image's line evidence agrees, in [0, 1]: the share of the segments' length
  // that supports the two vanishing points used. A heuristic for plots and gating, not a variance.
  double quality = 0.0;
  // RMS angle between the road's inlier segments and their lines through the vanishing point [rad].
  double road_residual_rms = 0.0;
  int segments = 0;         // usable segments after the length filter
  int road_inliers = 0;     // segments through the road's vanishing point
  int horizon_inliers = 0;  // segments through the vertical (or second) vanishing point

  bool usable() const { return !rejection.has_value(); }
};

inline FrameEstimate rejected_frame(FrameRejection rejection) {
  FrameEstimate estimate;
  estimate.rejection = rejection;
  return estimate;
}

// A per-frame estimator: the image (8-bit grey or BGR, as decoded) and the camera's intrinsics in,
// the frame's estimate out. Called concurrently from several threads, so it must not share
// mutable state between calls; it may throw only for a bug, never for a bad image (that is a
// rejection).
using FrameEstimator =
    std::function<FrameEstimate(const cv::Mat& image, const core::CameraIntrinsics& intrinsics)>;

// A first guess of the current frame's geometry for a SequenceEstimator (auto: the lines'
// vanishing point and gravity's horizon of the same frame), as in FrameEstimate.
struct SequenceGuide {
  Eigen::Vector2d vanishing_point_px = Eigen::Vector2d::Zero();  // [undistorted px]
  Eigen::Vector3d horizon_line = Eigen::Vector3d(0.0, 1.0, 0.0);
};

// A per-frame estimator that needs the frames before it as well (the motion estimator): the
// frames oldest first, the current one last, whose estimate it returns, and a guess of that
// frame's geometry when there is one. The same rules as FrameEstimator.
using SequenceEstimator = std::function<FrameEstimate(const std::vector<cv::Mat>& frames,
                                                      const core::CameraIntrinsics& intrinsics,
                                                      const std::optional<SequenceGuide>& guide)>;

}  // namespace x2car::camera
