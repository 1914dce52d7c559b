#include "x2car/camera/road_plane_motion.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/vanishing_rotation.hpp"

namespace x2car::camera {
namespace {

// Road points (z = 0 in the car frame at the first pose) seen by a camera mounted at `mounting`
// from two poses of the car: the first at the origin, the second after an arc of `chord_m` whose
// heading turned by `turn_rad` (on a circle the chord lies halfway between the two headings).
struct TwoViews {
  std::vector<Eigen::Vector2d> previous_px;
  std::vector<Eigen::Vector2d> current_px;
};

TwoViews road_in_two_views(const EulerAngles& mounting, const core::CameraIntrinsics& intrinsics,
                           double chord_m, double turn_rad, double noise_px, std::uint32_t seed,
                           const Eigen::Vector3d& camera_in_vehicle = {1.8, 0.1, 1.45}) {
  const Eigen::Matrix3d vehicle_from_optical = rotation_from_euler(mounting) * body_from_optical();
  const Eigen::Matrix3d second_heading =
      Eigen::AngleAxisd(turn_rad, Eigen::Vector3d::UnitZ()).matrix();
  const Eigen::Vector3d second_origin =
      chord_m * Eigen::Vector3d(std::cos(0.5 * turn_rad), std::sin(0.5 * turn_rad), 0.0);
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  const auto project = [&](const Eigen::Matrix3d& world_from_vehicle,
                           const Eigen::Vector3d& vehicle_origin,
                           const Eigen::Vector3d& point) -> std::optional<Eigen::Vector2d> {
    const Eigen::Matrix3d world_from_optical = world_from_vehicle * vehicle_from_optical;
    const Eigen::Vector3d centre = vehicle_origin + world_from_vehicle * camera_in_vehicle;
    const Eigen::Vector3d in_optical = world_from_optical.transpose() * (point - centre);
    if (in_optical.z() < 1.0) return std::nullopt;
    const Eigen::Vector3d pixel = camera_matrix * (in_optical / in_optical.z());
    if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() > intrinsics.width - 1 ||
        pixel.y() > intrinsics.height - 1) {
      return std::nullopt;
    }
    return pixel.head<2>();
  };
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> along(4.0, 40.0);
  std::uniform_real_distribution<double> across(-8.0, 8.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  TwoViews views;
  while (views.previous_px.size() < 300) {
    const Eigen::Vector3d point(along(random), across(random), 0.0);
    const auto first = project(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), point);
    const auto second = project(second_heading, second_origin, point);
    if (!first || !second) continue;
    const Eigen::Vector2d jitter_first(noise(random), noise(random));
    const Eigen::Vector2d jitter_second(noise(random), noise(random));
    views.previous_px.push_back(*first + (noise_px > 0 ? jitter_first : Eigen::Vector2d::Zero()));
    views.current_px.push_back(*second + (noise_px > 0 ? jitter_second : Eigen::Vector2d::Zero()));
  }
  return views;
}

EulerAngles angles_of(const FrameEstimate& estimate, const core::CameraIntrinsics& intrinsics) {
  const std::optional<EulerAngles> angles = vehicle_from_camera_angles(
      estimate.road_vanishing_point_px, estimate.horizon_line, intrinsics.camera_matrix());
  EXPECT_TRUE(angles.has_value());
  return angles.value_or(EulerAngles{});
}

TEST(RoadPlaneMotion, TracksThroughTheRoadsStretchDoNotTiltThePlane) {
  // Between two frames 1 m apart the road near the car stretches by up to 20 %; a Lucas-Kanade
  // window that is only shifted then follows its strongest texture (next to a line), and the
  // plane tilts: +0.4 deg of roll on the median on a rendered drive. Tracked again through the
  // first homography, the roll is the mounting's.
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(1.0), rad_from_deg(2.0), rad_from_deg(-1.0)};
  for (const double start : {0.0, 7.3, 14.6, 21.9}) {
    const std::vector<cv::Mat> frames{testing::road_picture(mounting, intrinsics, start),
                                      testing::road_picture(mounting, intrinsics, start + 1.0)};
    RoadPlaneMotionOptions options;
    options.max_lateral_over_height = 0.0;  // the whole width: this test is of the second tracking
    const FrameEstimate estimate = estimate_road_plane_motion(frames, intrinsics, options);
    ASSERT_TRUE(estimate.usable()) << to_string(*estimate.rejection);
    // Within 0.006 deg here; tracked once (prewarp off), pairs missed by up to 0.13 deg.
    EXPECT_NEAR(deg_from_rad(angles_of(estimate, intrinsics).roll - mounting.roll), 0.0, 0.05)
        << "after " << start << " m";
  }
}

// A camera pitched up 2.7 deg sees the road's horizon 35 px below the KITTI camera's centre, and a
// region placed for a level camera (3 deg below the centre) begins 4 px under it. With a guide the
// region begins 3 deg below the guide's horizon instead; a camera pitched down keeps the level
// camera's region.
TEST(RoadPlaneMotion, AGuideMovesTheRegionBelowAPitchedUpCamerasHorizon) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const RoadPlaneMotionOptions options;
  const double level_top_row =
      intrinsics.cy + intrinsics.fy * std::tan(options.road_region_depression);
  for (const double pitch_deg : {-2.7, 1.5}) {
    const EulerAngles mounting{0.0, rad_from_deg(pitch_deg), rad_from_deg(1.0)};
    const std::optional<VanishingGeometry> truth =
        vanishing_geometry_from_rotation(rotation_from_euler(mounting), intrinsics.camera_matrix());
    ASSERT_TRUE(truth);
    const SequenceGuide guide{truth->vanishing_point_px, truth->horizon_line};
    const std::vector<cv::Mat> frames{testing::road_picture(mounting, intrinsics, 5.0),
                                      testing::road_picture(mounting, intrinsics, 6.0)};
    const double guided_top_row =
        pitch_deg < 0.0 ? intrinsics.cy + intrinsics.fy * std::tan(rad_from_deg(-pitch_deg) +
                                                                   options.road_region_depression)
                        : level_top_row;
    const auto highest_row = [](const RoadTracks& tracks) {
      double highest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector2d& point : tracks.oldest_px) highest = std::min(highest, point.y());
      return highest;
    };
    const RoadTracks guided = road_plane_tracks(frames, intrinsics, options, guide);
    const RoadTracks unguided = road_plane_tracks(frames, intrinsics, options);
    ASSERT_FALSE(guided.oldest_px.empty());
    ASSERT_FALSE(unguided.oldest_px.empty());
    EXPECT_GE(highest_row(guided), guided_top_row - 1.0) << pitch_deg << " deg";
    EXPECT_GE(highest_row(unguided), level_top_row - 1.0) << pitch_deg << " deg";
    if (pitch_deg < 0.0) {
      EXPECT_LT(highest_row(unguided), guided_top_row - 10.0);  // tracks the guide leaves out
    }
  }
}

TEST(RoadPlaneMotion, ASidewalkBesideTheRoadDoesNotTiltThePlane) {
  // A sidewalk 15 cm above the road is another plane, and its slabs' joints are the strongest
  // corners in view: a homography fitted to road and sidewalk at once tilts (here by 0.7-1.3 deg
  // of roll a pair over the whole width). Corners are taken only within max_lateral_over_height.
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(-1.0), rad_from_deg(1.0), rad_from_deg(2.0)};
  RoadPlaneMotionOptions whole_width;
  whole_width.max_lateral_over_height = 0.0;
  double wedge_error_deg = 0.0, whole_width_error_deg = 0.0;
  const std::vector<double> starts{0.0, 7.3, 14.6, 21.9};
  for (const double start : starts) {
    const std::vector<cv::Mat> frames{
        testing::road_picture(mounting, intrinsics, start, 1.5, true),
        testing::road_picture(mounting, intrinsics, start + 1.0, 1.5, true)};
    const FrameEstimate estimate = estimate_road_plane_motion(frames, intrinsics);
    const FrameEstimate tilted = estimate_road_plane_motion(frames, intrinsics, whole_width);
    ASSERT_TRUE(estimate.usable() && tilted.usable()) << "after " << start << " m";
    wedge_error_deg += deg_from_rad(angles_of(estimate, intrinsics).roll - mounting.roll);
    whole_width_error_deg += deg_from_rad(angles_of(tilted, intrinsics).roll - mounting.roll);
  }
  // +0.14 deg on average here with the default wedge of 1.5 heights; -0.16 at 2 heights, where the
  // slabs next to the kerb reached into it near the car (the wedge is centred on the principal
  // point, and this camera is yawed 2 deg).
  EXPECT_NEAR(wedge_error_deg / starts.size(), 0.0, 0.25);
  EXPECT_GT(whole_width_error_deg / starts.size(), 0.5);
}

TEST(RoadPlaneMotion, AtHighwaySpeedTheSearchedSeedFindsTheRoad) {
  // 3 m between two frames (30 m/s at 10 Hz, twice the camera's height): the road near the car
  // moves by up to 100 px and stretches by a third. Tracked from the first tracks' homography
  // alone these pairs came out 0.2-0.8 deg off in roll and 0.1-0.25 deg in yaw; the search over
  // the travel, aimed by a guide as rough as the lines' vanishing point and gravity's horizon
  // (4 px and 0.4 deg off here) or by none (a level camera looking ahead, 2-3.5 deg off here),
  // seeds a second tracking whose fit maps the road better: within 0.05 deg guided, 0.09 unguided.
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const EulerAngles mounting{rad_from_deg(0.8), rad_from_deg(-2.0), rad_from_deg(3.5)};
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  const std::optional<VanishingGeometry> truth =
      vanishing_geometry_from_rotation(rotation_from_euler(mounting), camera_matrix);
  const EulerAngles rough{mounting.roll + rad_from_deg(0.4), mounting.pitch, mounting.yaw};
  const std::optional<VanishingGeometry> rough_geometry =
      vanishing_geometry_from_rotation(rotation_from_euler(rough), camera_matrix);
  ASSERT_TRUE(truth && rough_geometry);
  const SequenceGuide guide{truth->vanishing_point_px + Eigen::Vector2d(4.0, -3.0),
                            rough_geometry->horizon_line};
  for (const double start : {0.0, 7.3, 14.6}) {
    const std::vector<cv::Mat> frames{testing::road_picture(mounting, intrinsics, start),
                                      testing::road_picture(mounting, intrinsics, start + 3.0)};
    for (const std::optional<SequenceGuide>& given :
         {std::optional<SequenceGuide>(guide), std::optional<SequenceGuide>()}) {
      const FrameEstimate estimate = estimate_road_plane_motion(frames, intrinsics, {}, given);
      const std::string where = fmt::format("after {} m, {}", start, given ? "guided" : "unguided");
      ASSERT_TRUE(estimate.usable()) << to_string(*estimate.rejection) << " " << where;
      const EulerAngles found = angles_of(estimate, intrinsics);
      const double tolerance_deg = given ? 0.1 : 0.15;
      EXPECT_NEAR(deg_from_rad(found.roll - mounting.roll), 0.0, tolerance_deg) << where;
      EXPECT_NEAR(deg_from_rad(found.pitch - mounting.pitch), 0.0, tolerance_deg) << where;
      EXPECT_NEAR(deg_from_rad(found.yaw - mounting.yaw), 0.0, tolerance_deg) << where;
    }
  }
}

TEST(RoadPlaneMotion, RecoversTheMountingFromExactTracksDrivingStraight) {
  const core::CameraIntrinsics intrinsics;  // the KITTI-like default
  for (const EulerAngles mounting :
       {EulerAngles{0.0, 0.0, 0.0},
        EulerAngles{rad_from_deg(2.0), rad_from_deg(3.0), rad_from_deg(-4.0)},
        EulerAngles{rad_from_deg(-2.5), rad_from_deg(-1.0), rad_from_deg(3.0)}}) {
    const TwoViews views = road_in_two_views(mounting, intrinsics, 1.5, 0.0, 0.0, 7);
    const FrameEstimate estimate =
        road_plane_from_tracks(views.previous_px, views.current_px, intrinsics);
    ASSERT_TRUE(estimate.usable()) << to_string(*estimate.rejection);
    EXPECT_EQ(estimate.horizon_source, HorizonSource::kRoadPlaneMotion);
    EXPECT_EQ(estimate.road_inliers, 300);
    const EulerAngles found = angles_of(estimate, intrinsics);
    EXPECT_NEAR(deg_from_rad(found.roll), deg_from_rad(mounting.roll), 1e-4);
    EXPECT_NEAR(deg_from_rad(found.pitch), deg_from_rad(mounting.pitch), 1e-4);
    EXPECT_NEAR(deg_from_rad(found.yaw), deg_from_rad(mounting.yaw), 1e-4);
  }
}

// The roll is the road plane's, so the sign check of DESIGN §1 holds for it as for the horizon:
// a camera rolled left side up reports positive roll.
TEST(RoadPlaneMotion, RollSignFollowsTheRoadPlane) {
  const core::CameraIntrinsics intrinsics;
  const EulerAngles rolled{rad_from_deg(1.0), 0.0, 0.0};
  const TwoViews views = road_in_two_views(rolled, intrinsics, 1.5, 0.0, 0.0, 3);
  const FrameEstimate estimate =
      road_plane_from_tracks(views.previous_px, views.current_px, intrinsics);
  ASSERT_TRUE(estimate.usable());
  EXPECT_GT(horizon_angle(estimate.horizon_line), rad_from_deg(0.9));
  EXPECT_NEAR(deg_from_rad(angles_of(estimate, intrinsics).roll), 1.0, 1e-4);
}

// In a turn the chord between the frames is half a turn off either heading; the estimator turns
// it on, so a steady curve does not bias the yaw of a camera above the rear axle (where the car's
// velocity is along its x axis). Elsewhere the lever arm adds ω × r to the camera's velocity: the
// calibrator uses the translation's direction only on straight driving (docs/methods.md).
TEST(RoadPlaneMotion, ATurnBetweenTheFramesDoesNotBiasTheYawAboveTheRearAxle) {
  const core::CameraIntrinsics intrinsics;
  const EulerAngles mounting{rad_from_deg(0.5), rad_from_deg(2.0), rad_from_deg(1.0)};
  for (const double turn_deg : {-1.5, 0.8, 2.0}) {
    const TwoViews views = road_in_two_views(mounting, intrinsics, 1.2, rad_from_deg(turn_deg), 0.0,
                                             11, Eigen::Vector3d(0.0, 0.0, 1.45));
    const FrameEstimate estimate =
        road_plane_from_tracks(views.previous_px, views.current_px, intrinsics);
    ASSERT_TRUE(estimate.usable()) << turn_deg;
    const EulerAngles found = angles_of(estimate, intrinsics);
    EXPECT_NEAR(deg_from_rad(found.yaw), 1.0, 1e-3) << turn_deg;
    EXPECT_NEAR(deg_from_rad(found.pitch), 2.0, 1e-3) << turn_deg;
    EXPECT_NEAR(deg_from_rad(found.roll), 0.5, 1e-3) << turn_deg;
  }
}

// The pair's motion is the car's (the image motion gate reads it): its turn about the road's
// normal, left positive as the car's yaw, and its travel over the camera's height, whatever the
// mounting.
TEST(RoadPlaneMotion, ThePairsMotionIsTheCarsTurnAndTravelOverHeight) {
  const core::CameraIntrinsics intrinsics;
  const EulerAngles mounting{rad_from_deg(-1.5), rad_from_deg(3.0), rad_from_deg(2.5)};
  for (const double turn_deg : {-2.0, 0.0, 1.2}) {
    const TwoViews views = road_in_two_views(mounting, intrinsics, 1.6, rad_from_deg(turn_deg), 0.0,
                                             13, Eigen::Vector3d(1.2, -0.3, 1.45));
    const FrameEstimate estimate =
        road_plane_from_tracks(views.previous_px, views.current_px, intrinsics);
    ASSERT_TRUE(estimate.usable()) << turn_deg;
    ASSERT_TRUE(estimate.pair_motion.has_value()) << turn_deg;
    EXPECT_NEAR(deg_from_rad(estimate.pair_motion->turn_about_up), turn_deg, 1e-4);
    // Ahead of the rear axle the camera's chord is longer than the car's by the lever arm's turn.
    const Eigen::Vector3d lever(1.2, -0.3, 0.0);
    const Eigen::Vector3d camera_chord =
        1.6 * Eigen::Vector3d(std::cos(0.5 * rad_from_deg(turn_deg)),
                              std::sin(0.5 * rad_from_deg(turn_deg)), 0.0) +
        (Eigen::AngleAxisd(rad_from_deg(turn_deg), Eigen::Vector3d::UnitZ()).matrix() -
         Eigen::Matrix3d::Identity()) *
            lever;
    EXPECT_NEAR(estimate.pair_motion->travel_over_height, camera_chord.norm() / 1.45, 1e-5);
  }
  const TwoViews turning_right =
      road_in_two_views(mounting, intrinsics, 1.6, rad_from_deg(-0.7), 0.0, 13);
  const FrameEstimate right =
      road_plane_from_tracks(turning_right.previous_px, turning_right.current_px, intrinsics);
  ASSERT_TRUE(right.pair_motion.has_value());
  EXPECT_LT(right.pair_motion->turn_about_up, 0.0);  // turning right: negative, as the car's yaw
}

// Tracks with 0.2 px of noise (Lucas-Kanade on a textured road does about that): one pair's roll
// within 0.3 deg, pitch and yaw within 0.5 deg; averaging over the paper's windows does the rest.
TEST(RoadPlaneMotion, NoisyTracksGiveTheMountingToAFewTenthsOfADegree) {
  const core::CameraIntrinsics intrinsics;
  const EulerAngles mounting{rad_from_deg(-1.2), rad_from_deg(2.5), rad_from_deg(-2.0)};
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    const TwoViews views = road_in_two_views(mounting, intrinsics, 1.5, 0.0, 0.2, seed);
    const FrameEstimate estimate =
        road_plane_from_tracks(views.previous_px, views.current_px, intrinsics);
    ASSERT_TRUE(estimate.usable()) << seed;
    const EulerAngles found = angles_of(estimate, intrinsics);
    EXPECT_NEAR(deg_from_rad(found.roll), -1.2, 0.3) << seed;
    EXPECT_NEAR(deg_from_rad(found.pitch), 2.5, 0.5) << seed;
    EXPECT_NEAR(deg_from_rad(found.yaw), -2.0, 0.5) << seed;
  }
}

TEST(RoadPlaneMotion, RejectsTooLittleMotionAndTooFewTracks) {
  const core::CameraIntrinsics intrinsics;
  const EulerAngles mounting{0.0, rad_from_deg(1.0), 0.0};
  const TwoViews standing = road_in_two_views(mounting, intrinsics, 0.05, 0.0, 0.0, 5);
  const FrameEstimate still =
      road_plane_from_tracks(standing.previous_px, standing.current_px, intrinsics);
  ASSERT_FALSE(still.usable());
  EXPECT_EQ(*still.rejection, FrameRejection::kTooLittleMotion);

  TwoViews few = road_in_two_views(mounting, intrinsics, 1.5, 0.0, 0.0, 5);
  few.previous_px.resize(12);
  few.current_px.resize(12);
  const FrameEstimate sparse = road_plane_from_tracks(few.previous_px, few.current_px, intrinsics);
  ASSERT_FALSE(sparse.usable());
  EXPECT_EQ(*sparse.rejection, FrameRejection::kTooFewTracks);
}

TEST(RoadPlaneMotion, ImagesOfTheWrongSizeOrEmptyAreRejected) {
  const core::CameraIntrinsics intrinsics;
  const cv::Mat small(100, 200, CV_8UC1, cv::Scalar(128));
  EXPECT_EQ(*estimate_road_plane_motion({small, small}, intrinsics).rejection,
            FrameRejection::kWrongImageSize);
  EXPECT_EQ(*estimate_road_plane_motion({cv::Mat(), small}, intrinsics).rejection,
            FrameRejection::kUnreadableImage);
  // A featureless road: nothing to track.
  const cv::Mat flat(intrinsics.height, intrinsics.width, CV_8UC1, cv::Scalar(90));
  EXPECT_EQ(*estimate_road_plane_motion({flat, flat, flat}, intrinsics).rejection,
            FrameRejection::kTooFewTracks);
}

// The corners are looked for around the road region only; they must be exactly those of the whole
// image's search, for a mask in the image's middle, and for one on its edges.
TEST(RoadPlaneMotion, CornersInTheMaskAreThoseOfTheWholeImage) {
  cv::Mat noise(375, 1242, CV_8U);
  cv::RNG random(11);
  random.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat texture;
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 2.0);
  const auto wedge = [&](int top, int bottom, int left, int right) {
    cv::Mat mask = cv::Mat::zeros(texture.size(), CV_8U);
    const std::vector<cv::Point> corners{{(left + right) / 2 - 20, top},
                                         {(left + right) / 2 + 20, top},
                                         {right, bottom},
                                         {left, bottom}};
    cv::fillConvexPoly(mask, corners, cv::Scalar(255));
    return mask;
  };
  for (const cv::Mat& mask :
       {wedge(225, 374, 100, 1141), wedge(120, 300, 400, 900), wedge(200, 374, 0, 1241)}) {
    for (const double quality : {0.002, 0.0003}) {
      std::vector<cv::Point2f> expected;
      std::vector<float> expected_responses;
      cv::goodFeaturesToTrack(texture, expected, 800, quality, 6.0, mask, expected_responses);
      std::vector<cv::Point2f> corners;
      std::vector<float> responses;
      corners_in_mask(texture, mask, 800, quality, 6.0, corners, responses);
      ASSERT_GT(expected.size(), 100U);
      EXPECT_EQ(corners, expected);
      EXPECT_EQ(responses, expected_responses);
    }
  }
  std::vector<cv::Point2f> corners{{1.0F, 2.0F}};
  std::vector<float> responses{1.0F};
  corners_in_mask(texture, cv::Mat::zeros(texture.size(), CV_8U), 800, 0.002, 6.0, corners,
                  responses);
  EXPECT_TRUE(corners.empty());
  EXPECT_TRUE(responses.empty());
}

TEST(RoadPlaneMotion, OptionsAreChecked) {
  RoadPlaneMotionOptions options;
  options.min_inliers = 3;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_THROW(make_road_plane_motion_estimator(options), std::invalid_argument);
  EXPECT_NO_THROW(RoadPlaneMotionOptions().Check());
}

}  // namespace
}  // namespace x2car::camera
