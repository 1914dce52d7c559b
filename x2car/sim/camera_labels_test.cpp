#include "x2car/sim/camera_labels.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/camera_model.hpp"

namespace x2car::sim {
namespace {

using core::CameraIntrinsics;

// A road laid out by hand: stations every metre from -20 m, heading `heading` until `bend_at_m`,
// then turning at `curvature`; grade and crossfall constant until `bend_at_m`, then changing by
// `grade_rate` per metre.
struct RoadShape {
  double heading = 0.4;      // [rad]
  double grade = 0.03;       // [m/m]
  double crossfall = -0.02;  // [m/m]
  double bend_at_m = 1e9;    // [m]
  double curvature = 0.0;    // [1/m]
  double grade_rate = 0.0;   // [1/m]
};

RoadLayout make_road(const RoadShape& shape) {
  RoadLayout road;
  Eigen::Vector3d centre(10.0, -5.0, 2.0);
  double heading = shape.heading, grade = shape.grade;
  for (int i = -20; i <= 400; ++i) {
    RoadStation station;
    station.s = i;
    station.centre = centre;
    station.forward = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    station.left = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
    station.grade = grade;
    station.crossfall = shape.crossfall;
    station.route_offset = -1.75;  // the car in the right lane
    road.stations.push_back(station);
    centre += station.forward + grade * Eigen::Vector3d::UnitZ();
    if (i >= shape.bend_at_m) {
      heading += shape.curvature;
      grade += shape.grade_rate;
    }
  }
  road.segments.push_back({-20.0, 400.0, cross_section(Scenario::kUrban, {})});
  road.route_length = 380.0;
  return road;
}

// The car at arc length s on the road, its body rolled and pitched on its suspension.
VehicleState car_on(const RoadLayout& road, double s, double body_roll = 0.0,
                    double body_pitch = 0.0) {
  const RoadStation station = road.station_at(s);
  VehicleState state;
  state.time = 12.5;
  state.speed = 13.0;
  state.yaw_rate = 0.01;
  state.arc_length = s;
  state.world_from_vehicle.linear() = station.surface_rotation() *
                                      Eigen::AngleAxisd(body_pitch, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(body_roll, Eigen::Vector3d::UnitX());
  state.world_from_vehicle.translation() = station.surface_point(station.route_offset);
  return state;
}

Eigen::Isometry3d mounting(double roll_deg, double pitch_deg, double yaw_deg) {
  Eigen::Isometry3d vehicle_from_camera = Eigen::Isometry3d::Identity();
  vehicle_from_camera.linear() =
      rotation_from_euler({rad_from_deg(roll_deg), rad_from_deg(pitch_deg), rad_from_deg(yaw_deg)});
  vehicle_from_camera.translation() = Eigen::Vector3d(1.7, 0.1, 1.4);
  return vehicle_from_camera;
}

// A world point in the optical frame.
Eigen::Vector3d to_optical(const VehicleState& state, const Eigen::Isometry3d& vehicle_from_camera,
                           const Eigen::Vector3d& point_world) {
  // Composed here by hand (not with world_from_camera_optical) so that the test checks it.
  const Eigen::Matrix3d world_from_optical =
      state.world_from_vehicle.linear() * vehicle_from_camera.linear() * camera_body_from_optical();
  const Eigen::Vector3d optical_in_world =
      state.world_from_vehicle * vehicle_from_camera.translation();
  return world_from_optical.transpose() * (point_world - optical_in_world);
}

// The homogeneous line through two pixels.
Eigen::Vector3d line_through(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  return p.homogeneous().cross(q.homogeneous());
}

TEST(CameraLabels, LaneEdgesOfAStraightRoadMeetAtTheRoadVanishingPoint) {
  const RoadLayout road = make_road({});
  const VehicleState state = car_on(road, 50.0, rad_from_deg(1.2), rad_from_deg(-0.8));
  const Eigen::Isometry3d camera = mounting(-1.5, 3.0, 2.0);
  for (const std::string& preset : core::camera_preset_names()) {
    const CameraIntrinsics intrinsics = core::camera_preset(preset);
    const CameraFrameLabel label = camera_frame_label(intrinsics, camera, state, road);
    ASSERT_TRUE(label.road_vp.has_value());
    ASSERT_TRUE(label.road_vp->distorted_px.has_value());
    // Each edge of the car's lane (lateral -3.5 and 0 m), seen at 15 and 120 m ahead: projected
    // through the intrinsics and the distortion, then undistorted, as a calibrator would.
    std::vector<Eigen::Vector3d> edges;
    for (const double lateral : {-3.5, 0.0}) {
      std::vector<Eigen::Vector2d> pixels;
      for (const double ahead : {15.0, 120.0}) {
        const Eigen::Vector3d point = road.station_at(50.0 + ahead).surface_point(lateral);
        const auto pixel = core::project_to_pixel(intrinsics, to_optical(state, camera, point));
        ASSERT_TRUE(pixel.has_value()) << preset;
        pixels.push_back(core::undistort_pixel(intrinsics, *pixel));
      }
      edges.push_back(line_through(pixels[0], pixels[1]));
    }
    const Eigen::Vector3d meet = edges[0].cross(edges[1]);
    const Eigen::Vector2d vp = meet.head<2>() / meet.z();
    EXPECT_LT((vp - label.road_vp->undistorted_px).norm(), 0.5) << preset;
    // The distorted VP is where a far point along the lane lands in the image.
    const Eigen::Vector3d far = road.station_at(50.0).surface_point(-1.75) +
                                1e7 * road.station_at(50.0).surface_rotation().col(0);
    const auto far_pixel = core::project_to_pixel(intrinsics, to_optical(state, camera, far));
    ASSERT_TRUE(far_pixel.has_value());
    EXPECT_LT((*far_pixel - *label.road_vp->distorted_px).norm(), 0.5) << preset;
    // The road VP lies on the road's horizon; the distances are in pixels.
    ASSERT_TRUE(label.road_horizon.has_value());
    EXPECT_NEAR(label.road_horizon->line.dot(label.road_vp->undistorted_px.homogeneous()), 0.0,
                1e-6);
    EXPECT_NEAR(label.road_horizon->line.head<2>().norm(), 1.0, 1e-12);
    // A point on the road lies on the ground side (negative); a point above the horizon on the sky
    // side.
    const Eigen::Vector3d ground = road.station_at(60.0).surface_point(-1.75);
    const auto ground_pixel = core::project_to_pixel(intrinsics, to_optical(state, camera, ground));
    ASSERT_TRUE(ground_pixel.has_value());
    EXPECT_LT(label.road_horizon->line.dot(
                  core::undistort_pixel(intrinsics, *ground_pixel).homogeneous()),
              -10.0);
  }
}

TEST(CameraLabels, SignChecksOfDesignSection1) {
  // A level, straight road and a car level on it: only the mounting moves the VP and horizon.
  RoadShape flat;
  flat.grade = 0.0;
  flat.crossfall = 0.0;
  const RoadLayout road = make_road(flat);
  const VehicleState state = car_on(road, 50.0);
  const CameraIntrinsics c;  // kitti
  const auto label = [&](double roll_deg, double pitch_deg, double yaw_deg) {
    return camera_frame_label(c, mounting(roll_deg, pitch_deg, yaw_deg), state, road);
  };
  const double f = c.fx;

  const CameraFrameLabel level = label(0.0, 0.0, 0.0);
  EXPECT_NEAR(level.forward_vp->undistorted_px.x(), c.cx, 1e-9);
  EXPECT_NEAR(level.forward_vp->undistorted_px.y(), c.cy, 1e-9);
  EXPECT_NEAR(level.level_horizon->angle, 0.0, 1e-12);
  EXPECT_NEAR(level.level_horizon->offset_px, 0.0, 1e-9);

  // Pitched down: the VP above the image centre (smaller v), the horizon above the principal
  // point by f tan(pitch).
  const CameraFrameLabel down = label(0.0, 3.0, 0.0);
  EXPECT_NEAR(down.road_vp->undistorted_px.y(), c.cy - f * std::tan(rad_from_deg(3.0)), 1e-9);
  EXPECT_LT(down.road_vp->undistorted_px.y(), c.height / 2.0 - 30.0);
  EXPECT_NEAR(down.level_horizon->offset_px, f * std::tan(rad_from_deg(3.0)), 1e-9);
  EXPECT_NEAR(down.road_horizon->offset_px, down.level_horizon->offset_px, 1e-9);

  // Yawed left (+yaw): the car's forward direction appears right of centre.
  const CameraFrameLabel left = label(0.0, 0.0, 4.0);
  EXPECT_NEAR(left.forward_vp->undistorted_px.x(), c.cx + f * std::tan(rad_from_deg(4.0)), 1e-9);
  EXPECT_GT(left.road_vp->undistorted_px.x(), c.width / 2.0 + 30.0);

  // Rolled +2 deg (left side up): the horizon's right end rises, angle +2 deg counter-clockwise
  // on screen; its v falls (rises on screen) from left to right.
  const CameraFrameLabel rolled = label(2.0, 0.0, 0.0);
  EXPECT_NEAR(rolled.level_horizon->angle, rad_from_deg(2.0), 1e-12);
  const Eigen::Vector3d l = rolled.level_horizon->line;
  const auto v_at = [&](double u) { return -(l.x() * u + l.z()) / l.y(); };
  EXPECT_LT(v_at(c.width - 1.0), v_at(0.0) - 30.0);

  // A body pitched down on its suspension (nose dive) moves the horizons too, not the forward VP.
  const CameraFrameLabel dive = camera_frame_label(
      c, mounting(0.0, 0.0, 0.0), car_on(road, 50.0, 0.0, rad_from_deg(1.0)), road);
  EXPECT_NEAR(dive.forward_vp->undistorted_px.y(), c.cy, 1e-9);
  EXPECT_NEAR(dive.level_horizon->offset_px, f * std::tan(rad_from_deg(1.0)), 1e-9);
}

TEST(CameraLabels, RoadAndLevelHorizonsPartOnAGradeAndACrossfall) {
  RoadShape uphill;
  uphill.grade = 0.05;
  uphill.crossfall = 0.0;
  const RoadLayout road = make_road(uphill);
  const CameraIntrinsics c;
  const CameraFrameLabel label =
      camera_frame_label(c, mounting(0.0, 0.0, 0.0), car_on(road, 50.0), road);
  // Uphill the car is pitched up with the road: the level horizon is f tan(atan 0.05) below the
  // principal point; the road's horizon stays at it.
  EXPECT_NEAR(label.level_horizon->offset_px, -c.fx * 0.05, 1e-9);
  EXPECT_NEAR(label.road_horizon->offset_px, 0.0, 1e-9);
  EXPECT_TRUE(label.straight);
  EXPECT_TRUE(label.level);
  EXPECT_EQ(label.time, 12.5);
  EXPECT_EQ(label.speed_mps, 13.0);
  EXPECT_EQ(label.yaw_rate, 0.01);
}

TEST(CameraLabels, FlagsSayWhetherTheRoadAheadIsStraightAndLevel) {
  const CameraIntrinsics c;
  const Eigen::Isometry3d camera = mounting(0.0, 1.0, 0.0);
  RoadShape bend;
  bend.bend_at_m = 80.0;
  bend.curvature = 1e-3;  // R = 1 km, 30 m ahead of a car at 50 m: within the 50 m look-ahead
  RoadLayout road = make_road(bend);
  EXPECT_TRUE(camera_frame_label(c, camera, car_on(road, 20.0), road).straight);
  EXPECT_FALSE(camera_frame_label(c, camera, car_on(road, 50.0), road).straight);
  EXPECT_TRUE(camera_frame_label(c, camera, car_on(road, 50.0), road).level);
  RoadShape crest;
  crest.bend_at_m = 80.0;
  crest.grade_rate = -5e-4;  // 0.005 in 10 m
  road = make_road(crest);
  EXPECT_TRUE(camera_frame_label(c, camera, car_on(road, 20.0), road).level);
  EXPECT_FALSE(camera_frame_label(c, camera, car_on(road, 50.0), road).level);
  EXPECT_TRUE(camera_frame_label(c, camera, car_on(road, 50.0), road).straight);
  CameraLabelOptions bad;
  bad.lookahead_m = 0.0;
  EXPECT_THROW(camera_frame_label(c, camera, car_on(road, 50.0), road, bad), std::invalid_argument);
}

TEST(CameraLabels, CsvRowsHaveTheHeadersColumnsAndEmptyFieldsForAbsentValues) {
  const RoadLayout road = make_road({});
  const CameraFrameLabel label = camera_frame_label(
      core::camera_preset("dashcam_wide"), mounting(1.0, 2.0, 3.0), car_on(road, 50.0), road);
  const std::string header = format_camera_labels_csv_header();
  const std::string row = format_camera_label_row(label);
  const auto fields = [](const std::string& line) { return io::split_fields(io::trim(line)); };
  ASSERT_EQ(fields(header).size(), 23u);
  ASSERT_EQ(fields(row).size(), 23u);
  EXPECT_THAT(header,
              ::testing::StartsWith("time,speed_mps,yaw_rate,straight,level,forward_vp_u,"));
  EXPECT_EQ(fields(row)[0], "12.5");
  EXPECT_EQ(fields(row)[3], "1");
  EXPECT_EQ(fields(row)[5], io::format_number(label.forward_vp->undistorted_px.x()));
  EXPECT_EQ(fields(row)[22], io::format_number(label.level_horizon->line.z()));

  // A label with a road VP outside the distortion's domain and no level horizon.
  CameraFrameLabel empty;
  empty.road_vp.emplace();
  empty.road_vp->undistorted_px = Eigen::Vector2d(1.0, 2.0);
  empty.road_horizon.emplace();
  const auto empty_fields = fields(format_camera_label_row(empty));
  ASSERT_EQ(empty_fields.size(), 23u);
  EXPECT_EQ(empty_fields[11], "");  // road_vp_u_distorted
  EXPECT_EQ(empty_fields[18], "");  // level_horizon_angle
  EXPECT_EQ(empty_fields[22], "");
  // A VP of a direction behind the camera does not exist.
  EXPECT_FALSE(vanishing_point(core::CameraIntrinsics{}, {0.0, 0.0, -1.0}).has_value());
  EXPECT_FALSE(horizon_line(core::CameraIntrinsics{}, {0.0, 0.0, 1.0}).has_value());
}

}  // namespace
}  // namespace x2car::sim
