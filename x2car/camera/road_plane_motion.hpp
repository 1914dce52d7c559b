// The motion estimator (issue 14 item 2): the road plane and the car's travel from a few
// consecutive frames, so that the horizon is the road's, not gravity's.
//
// The vertical vanishing point of the geometric estimator gives gravity's horizon; on a road with
// crossfall the car leans against gravity, and that lean enters the roll (docs/methods.md, camera
// §4). The road itself is a plane under the car, parallel to the car's x-y plane (its wheels stand
// on it), and between two frames the image of a plane moves by a homography
//
//   x2 ~ H x1,   H = R + t n^T / d                                   (Hartley & Zisserman, 13.1)
//
// (x the normalised image points, R and t the camera's motion X2 = R X1 + t, n the plane's unit
// normal and d its distance, n^T X1 = d, in the first camera's optical frame). So, per frame, with
// the `tracked_frames` - 1 frames before it:
//   1. corners (Shi-Tomasi) in the lower part of the oldest image, where the road is, tracked
//      frame by frame into the current one by pyramidal Lucas-Kanade, forward and back (a track
//      that does not come back to its start within `max_forward_backward_px` is dropped): the
//      steps stay small for the tracker while the baseline, and so the parallax, grows; then
//      (prewarp) tracked again from where the homography of those tracks puts them; and, beside
//      that, from where a searched homography of straight travel puts them (the road's
//      correlation over the one unknown travel over height: at highway speed the first tracks
//      give no homography or a wrong one). Of the two fits, the one whose homography maps the
//      oldest image's road onto the current one better is kept;
//   2. the tracks undistorted (core::undistort_pixel) and normalised by K;
//   3. the plane's homography by RANSAC (the points not on the road: kerbs, sidewalks, cars, are
//      its outliers), refined by least squares on the inliers (OpenCV findHomography);
//   4. H decomposed (Malis & Vargas 2007, OpenCV decomposeHomographyMat); of its solutions the
//      one whose normal points down (+y in the optical frame: the road lies below the camera);
//   5. the car's up direction in the current frame is -R n; its forward direction is the chord
//      -R^T t turned back by half the frame pair's rotation (on a steady curve the chord lies
//      halfway between the two headings), then expressed in the current frame.
// The result is a FrameEstimate like the geometric one: the forward direction's vanishing point
// (pitch and yaw) and the road plane's horizon (roll; HorizonSource::kRoadPlaneMotion).
//
// What it needs: texture on the road (lane paint, its dashes' ends, patches, shadows of things
// that stand still), and motion: a pair whose translation is below `min_translation_over_height`
// of the camera's height above the road is rejected (too_little_motion): the plane's normal comes
// from the parallax, which vanishes with the baseline.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "x2car/camera/frame_estimate.hpp"
#include "x2car/core/camera_model.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera {

struct RoadPlaneMotionOptions {
  // Frames a track runs through, the current one included (2: a frame and the one before). The
  // road's parallax grows with the baseline, but a longer track is lost more often: on the
  // simulator's rendered road 3 frames kept a fifth of the frames 2 did (docs/methods.md).
  int tracked_frames = 2;
  // Corners looked for in the oldest image (Shi-Tomasi), at most this many.
  int max_features = 800;
  // Their weakest corner response relative to the strongest (goodFeaturesToTrack's qualityLevel):
  // low, because asphalt has little contrast.
  double feature_quality = 0.002;
  // Corners at least this far apart [px].
  double min_feature_distance_px = 6.0;
  // Only below the row that a ray this far below the optical axis meets [rad]: above it, the
  // road's share of the image shrinks and the background takes over. Mountings pitched up by more
  // than this see some background in the region; RANSAC drops it.
  double road_region_depression = rad_from_deg(3.0);
  // ... and only where a level camera sees the road at most this many times its height to either
  // side (a wedge below the principal point; 0: the whole width): the car's lane and a little
  // beyond (1.5 x 1.4 m; a lane is 3-3.75 m wide). Kerbs, sidewalks and verges are other planes,
  // and a homography fitted to road and sidewalk at once tilts: with perfect tracks, +0.5 deg of
  // roll on rendered urban 302; with tracked corners and a kerb at the lane's edge, +0.27 deg at
  // 2 heights on urban 303.
  double max_lateral_over_height = 1.5;
  // With a guide, the region's top row is `road_region_depression` below the guide's road
  // horizon when that lies below the principal point (a camera pitched up), instead of below the
  // principal point. A camera pitched up 2.7 deg sees the road's horizon 35 px below the KITTI
  // camera's centre: a region placed for a level camera began 4 px under it, where the road is far
  // and moves little, and two such one-minute drives gave no result (docs/methods.md, camera §5;
  // both calibrate now). A camera pitched down keeps the level camera's region, and the wedge stays
  // about the principal point.
  bool road_region_at_guide = true;
  // Lucas-Kanade window [px] and pyramid levels (a level halves the image; the flow near the
  // image's bottom edge reaches tens of pixels per frame).
  int tracking_window_px = 21;
  int pyramid_levels = 4;
  // Track again through the road's first homography: the oldest image warped by the homography
  // that its tracks fit, each corner followed from where it predicts. Lucas-Kanade moves a window
  // without deforming it, but between two frames the road near the car stretches (by 17 % at 7 m
  // ahead, 10 m/s, 10 Hz) and a track then follows wherever the window's texture is strongest:
  // on rendered drives its errors were one-sided and tilted the plane by +0.4 deg in roll
  // (docs/methods.md). After the warp what is left to track is a small shift.
  bool prewarp = true;
  // With `prewarp`, a second seed beside the tracks' homography: a search over the one unknown of
  // straight driving, the travel over the camera's height |t| / d, between
  // `min_translation_over_height` and this. For each candidate the oldest image is warped by the
  // road's homography (the car's forward direction and the road's normal from the guide when one
  // is given, else from a level camera looking straight ahead) and compared with the current one
  // over the road region (correlation, at half resolution); the best seeds a second tracking, and
  // of the two fits the one whose homography correlates better is kept. At highway speed (2.5-3 m
  // between frames at 10 Hz, up to twice the camera's height) the road near the car moves by
  // 50-100 px and stretches by a third: the first tracks then give no homography, or a wrong one
  // that the second tracking follows (0.2-0.8 deg of roll on the tests' pairs 3 m apart). 0: no
  // search.
  double max_seed_travel_over_height = 3.0;
  // The corners tracked from the searched seed: weaker ones than `feature_quality` (0.0003: on a
  // highway the lane paint's corners set the scale, and only ~50 asphalt corners a frame pass
  // 0.002), which after the warp are followed over a small shift only.
  double seeded_feature_quality = 0.0003;
  // A track must come back to its start within this when tracked back [px].
  double max_forward_backward_px = 0.5;
  // RANSAC's inlier threshold for the homography (in the current image) [px].
  double ransac_threshold_px = 1.0;
  // Fewer homography inliers than this: no_road_plane.
  int min_inliers = 40;
  // The translation between the frames over the camera's height above the road, |t| / d, below
  // which the pair is too_little_motion (0.15: 0.2 m at a height of 1.4 m; 2 m/s at 10 Hz).
  double min_translation_over_height = 0.15;
  // The rotation between the oldest and the current frame above which the frame is rejected
  // (no_road_plane) [rad]: beyond it either the decomposition went wrong or the car turned too
  // hard for the chord to be its heading.
  double max_rotation = rad_from_deg(3.0);
  // The road's normal within this angle of the optical frame's +y (down) [rad]: mountings of
  // +-10 deg and a road's grade stay inside; a wall or a car that fills the view does not.
  double max_normal_tilt = rad_from_deg(25.0);

  // Pixels to leave out of the road region (8-bit, the images' size; nonzero: the car's own body,
  // car_region.hpp). Empty: none.
  cv::Mat ignored_region;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// Frames a short time apart, oldest first, the current one last (8 or 16 bit, grey or BGR, the
// intrinsics' size; at least two) -> the current frame's estimate: the car's forward vanishing
// point and the road plane's horizon, or why not (too_few_tracks, too_little_motion,
// no_road_plane, wrong_image_size, unreadable_image). `guide` (the current frame's vanishing point
// and horizon from elsewhere) only aims the seed search of `max_seed_travel_over_height`. Pure:
// safe to call from several threads.
FrameEstimate estimate_road_plane_motion(const std::vector<cv::Mat>& frames,
                                         const core::CameraIntrinsics& intrinsics,
                                         const RoadPlaneMotionOptions& options = {},
                                         const std::optional<SequenceGuide>& guide = std::nullopt);

// Step 1 alone: the tracks of the estimate estimate_road_plane_motion makes (the second tracking's
// when `prewarp`, from the searched seed where that fit maps the road better), in distorted pixels
// of the oldest frame and of the current one, as many of each; none when a frame is empty or of
// another size than the intrinsics'. For studies of the tracker (bench/camera_track_study.cpp).
struct RoadTracks {
  std::vector<Eigen::Vector2d> oldest_px;
  std::vector<Eigen::Vector2d> current_px;
};
RoadTracks road_plane_tracks(const std::vector<cv::Mat>& frames,
                             const core::CameraIntrinsics& intrinsics,
                             const RoadPlaneMotionOptions& options = {},
                             const std::optional<SequenceGuide>& guide = std::nullopt);

// Step 1's corners: Shi-Tomasi corners of `image` (8-bit grey) inside `mask` (8-bit, its size),
// strongest first, at most `max_corners`, responses above `quality` of the strongest, at least
// `min_distance_px` apart, with their responses: exactly those of cv::goodFeaturesToTrack over the
// whole image, at the cost of the mask's bounding box (the road region is under half the image).
void corners_in_mask(const cv::Mat& image, const cv::Mat& mask, int max_corners, double quality,
                     double min_distance_px, std::vector<cv::Point2f>& corners,
                     std::vector<float>& responses);

// Steps 2-5 on tracks already made: `previous_px` (in the oldest frame) and `current_px` are
// distorted pixels of the same road points (as many of each).
FrameEstimate road_plane_from_tracks(const std::vector<Eigen::Vector2d>& previous_px,
                                     const std::vector<Eigen::Vector2d>& current_px,
                                     const core::CameraIntrinsics& intrinsics,
                                     const RoadPlaneMotionOptions& options = {});

// The same behind the SequenceEstimator interface. Checks the options once (std::invalid_argument).
SequenceEstimator make_road_plane_motion_estimator(const RoadPlaneMotionOptions& options = {});

}  // namespace x2car::camera
