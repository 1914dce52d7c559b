#include "x2car/camera/frame_views.hpp"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/error.hpp"

namespace x2car::camera {
namespace {

const EulerAngles kViewMounting{rad_from_deg(0.8), rad_from_deg(2.0), rad_from_deg(-1.5)};

CameraFrameSource frames_of(const cv::Mat& image, std::size_t count) {
  CameraFrameSource frames;
  for (std::size_t i = 0; i < count; ++i) frames.times.push_back(0.1 * static_cast<double>(i));
  frames.read = [image](std::size_t) { return image; };
  return frames;
}

cv::Mat decoded(const FrameView& view) {
  const std::vector<unsigned char> bytes(view.jpeg.begin(), view.jpeg.end());
  return cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
}

// The exact vanishing point and horizon of the drawn street, in the view's pixels.
VanishingGeometry exact_in_view(const FrameView& view) {
  return *vanishing_geometry_from_rotation(rotation_from_euler(kViewMounting),
                                           view.intrinsics.camera_matrix());
}

double distance_to_line(const Eigen::Vector3d& line, const Eigen::Vector2d& point) {
  return std::abs(line.x() * point.x() + line.y() * point.y() + line.z()) / line.head<2>().norm();
}

// Scaled to half width, the view's K, vanishing point, horizon and lines stay the scene's: the
// vanishing point within 1 px of the exact one in the view, the horizon through the exact one's
// points, and the JPEG of the view's size.
TEST(FrameViews, ScaledViewsKeepTheirGeometry) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  testing::StreetScene scene;
  scene.vehicle_from_camera = kViewMounting;
  FrameViewOptions options;
  options.count = 1;
  options.max_width_px = intrinsics.width / 2;
  const std::vector<FrameView> views = sample_frame_views(
      frames_of(testing::draw_street(scene, intrinsics), 5), intrinsics, options);
  ASSERT_EQ(views.size(), 1U);
  const FrameView& view = views[0];
  ASSERT_TRUE(view.estimate.usable());
  EXPECT_EQ(view.intrinsics.width, 621);
  EXPECT_EQ(view.intrinsics.height, 188);
  EXPECT_EQ(view.intrinsics.distortion_model, core::DistortionModel::kNone);
  const cv::Mat image = decoded(view);
  EXPECT_EQ(image.cols, 621);
  EXPECT_EQ(image.rows, 188);
  const VanishingGeometry exact = exact_in_view(view);
  EXPECT_LT((view.estimate.road_vanishing_point_px - exact.vanishing_point_px).norm(), 1.0);
  for (const double u : {0.0, 300.0, 620.0}) {
    const double v =
        -(exact.horizon_line.x() * u + exact.horizon_line.z()) / exact.horizon_line.y();
    EXPECT_LT(distance_to_line(view.estimate.horizon_line, {u, v}), 1.0) << "at u = " << u;
  }
  int road_lines = 0;
  for (const FrameLine& line : view.lines) {
    if (line.role != LineRole::kRoad) continue;
    ++road_lines;
    // A road segment, extended, passes the vanishing point (within the estimator's 1 deg).
    const Eigen::Vector3d through =
        Eigen::Vector3d(line.start_px.x(), line.start_px.y(), 1.0)
            .cross(Eigen::Vector3d(line.end_px.x(), line.end_px.y(), 1.0));
    const double reach = (line.start_px - exact.vanishing_point_px).norm();
    EXPECT_LT(distance_to_line(through, exact.vanishing_point_px), 0.03 * reach + 1.0);
  }
  EXPECT_GE(road_lines, 6);
}

// A fisheye frame is shown undistorted: the estimator run again on the shown (pinhole) JPEG finds
// the vanishing point where the view says it is, so the drawn lines sit on the image.
TEST(FrameViews, DistortedFramesAreShownUndistorted) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("dashcam_wide");
  testing::StreetScene scene;
  scene.vehicle_from_camera = kViewMounting;
  scene.noise_grey = 0.0;
  FrameViewOptions options;
  options.count = 1;
  const std::vector<FrameView> views = sample_frame_views(
      frames_of(testing::draw_street_distorted(scene, intrinsics), 3), intrinsics, options);
  ASSERT_EQ(views.size(), 1U);
  const FrameView& view = views[0];
  ASSERT_TRUE(view.estimate.usable());
  EXPECT_EQ(view.intrinsics.width, 1280);
  const VanishingGeometry exact = exact_in_view(view);
  EXPECT_LT((view.estimate.road_vanishing_point_px - exact.vanishing_point_px).norm(), 2.0);
  const FrameEstimate again = estimate_frame_geometric(decoded(view), view.intrinsics);
  ASSERT_TRUE(again.usable()) << to_string(*again.rejection);
  EXPECT_LT((again.road_vanishing_point_px - view.estimate.road_vanishing_point_px).norm(), 2.0);
}

// Frames spread over the log, an unreadable one passed over for the next.
TEST(FrameViews, SpreadOverTheLogPassingUnreadableFrames) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  testing::StreetScene scene;
  scene.vehicle_from_camera = kViewMounting;
  CameraFrameSource frames = frames_of(testing::draw_street(scene, intrinsics), 40);
  const cv::Mat image = frames.read(0);
  frames.read = [image](std::size_t index) -> cv::Mat {
    if (index == 5) throw InputError("frame5.png", "truncated");
    return image;
  };
  FrameViewOptions options;
  options.count = 4;
  const std::vector<FrameView> views = sample_frame_views(frames, intrinsics, options);
  ASSERT_EQ(views.size(), 4U);
  EXPECT_EQ(views[0].index, 6U);  // 5 is the first quarter's middle, and unreadable
  EXPECT_EQ(views[1].index, 15U);
  EXPECT_EQ(views[2].index, 25U);
  EXPECT_EQ(views[3].index, 35U);
  EXPECT_DOUBLE_EQ(views[3].time_s, 3.5);
  EXPECT_EQ(views[3].name, "frame 35");
}

TEST(FrameViews, OptionsAreChecked) {
  FrameViewOptions options;
  options.count = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.jpeg_quality = 101;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::camera
