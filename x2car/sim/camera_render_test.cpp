#include "x2car/sim/camera_render.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>

#include "x2car/core/rotation.hpp"
#include "x2car/sim/camera_labels.hpp"
#include "x2car/sim/camera_model.hpp"
#include "x2car/sim/camera_rays.hpp"
#include "x2car/sim/camera_shading.hpp"
#include "x2car/sim/world_mesh.hpp"

namespace x2car::sim {
namespace {

// ---- a scene made for the tests --------------------------------------------------------------
//
// A flat straight urban road along +x from the ENU origin, without roadside objects or traffic,
// inside a grass plain 3 km wide (so that the ground meets the sky at the horizon), and the car
// standing on its route line at x = 100 m facing +x. The camera is 1.5 m ahead of the rear axle,
// 1.4 m up; 640x200 px with fx = fy = 200 px (116 deg across), so that both edge lines of the
// urban road are in view.

constexpr double kCarX = 100.0;
constexpr double kRouteLength = 3000.0;

Route flat_straight_route() {
  RoadPlan plan;
  plan.curvature = {{0.0, 0.0}, {kRouteLength, 0.0}};
  return Route(plan, VerticalProfile{});
}

World bare_street() {
  WorldOptions options;
  RoadsideOptions& roadside = options.roadside;
  roadside.building_frontage = 0.0;
  roadside.pole_spacing_m = roadside.sign_spacing_m = roadside.tree_spacing_m = 0.0;
  roadside.parked_car_spacing_m = 0.0;
  TrafficOptions& traffic = options.traffic;
  traffic.oncoming_cars_per_km = traffic.cyclists_per_km = traffic.highway_cars_per_km_lane = 0.0;
  World world = generate_world(flat_straight_route(), Scenario::kUrban, {}, options, 1);
  WorldObject plain;
  plain.id = static_cast<std::uint32_t>(world.objects.size());
  plain.kind = ObjectKind::kRoad;  // a flat strip (kTerrain would be a height field)
  plain.material = standard_material(Surface::kGrass);
  plain.strip = RoadStrip{world.road.s_begin(), world.road.s_end(), -3000.0, 3000.0, -0.3, -0.3};
  world.objects.push_back(plain);
  return world;
}

VehicleStates standing_car() {
  VehicleStates states(2);
  for (int k = 0; k < 2; ++k) {
    states[k].time = k;
    states[k].world_from_vehicle.translation() = Eigen::Vector3d(kCarX, 0.0, 0.0);
  }
  return states;
}

core::CameraIntrinsics wide_camera() {
  core::CameraIntrinsics intrinsics;
  intrinsics.width = 640;
  intrinsics.height = 200;
  intrinsics.fx = intrinsics.fy = 200.0;
  intrinsics.cx = 319.5;
  intrinsics.cy = 99.5;
  return intrinsics;
}

// Exact pictures: no noise, vignetting, shadows or haze.
CameraRenderOptions clean_options() {
  CameraRenderOptions options;
  options.read_noise = options.shot_noise = 0.0;
  options.vignetting = 0.0;
  options.shadows = false;
  options.haze_distance_m = 1e7;
  return options;
}

Eigen::Isometry3d camera_mounting(double roll_deg, double pitch_deg, double yaw_deg) {
  return make_transform(
      EulerAngles{rad_from_deg(roll_deg), rad_from_deg(pitch_deg), rad_from_deg(yaw_deg)},
      Eigen::Vector3d(1.5, 0.0, 1.4));
}

struct Shot {
  World world;
  VehicleStates states = standing_car();
  core::CameraIntrinsics intrinsics = wide_camera();
  Eigen::Isometry3d vehicle_from_camera;
  RgbImage image;

  Eigen::Isometry3d world_from_optical() const {
    return world_from_camera_optical(states.front().world_from_vehicle, vehicle_from_camera);
  }
  // The camera model's projection of a world point (distortion included; the car stands still).
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& point_world) const {
    return core::project_to_pixel(intrinsics, world_from_optical().inverse() * point_world);
  }
  // The vanishing point of the direction `direction_world` in undistorted pixels, as the labels
  // give it (camera_labels.hpp).
  Eigen::Vector2d vanishing_point(const Eigen::Vector3d& direction_world) const {
    return sim::vanishing_point(intrinsics,
                                world_from_optical().linear().transpose() * direction_world)
        ->undistorted_px;
  }
  // Linear light of one channel (the renderer averages light linearly, so coverage is linear).
  double light(int u, int v, int channel) const {
    return linear_from_srgb8(image.at(u, v, channel));
  }
};

Shot render_shot(World world, const Eigen::Isometry3d& vehicle_from_camera,
                 const CameraRenderOptions& options = clean_options(),
                 const core::CameraIntrinsics& intrinsics = wide_camera()) {
  Shot shot{std::move(world), standing_car(), intrinsics, vehicle_from_camera, {}};
  const WorldScene scene(shot.world);
  const CameraRenderer camera(scene, shot.states, vehicle_from_camera, shot.intrinsics, options, 7);
  shot.image = camera.render(0);
  return shot;
}

// ---- measuring edges in the image -------------------------------------------------------------

// Where a step edge lies in the profile values(k), k = first..last, whose ends are pure (one side
// at `first`, the other at `last`): each pixel's value is the share of it covered by the first
// side, so the edge is at first - 0.5 + the sum of those shares [pixels].
double step_edge(int first, int last, const std::function<double(int)>& values) {
  const double a = values(first), b = values(last);
  double covered = 0.0;
  for (int k = first; k <= last; ++k) covered += std::clamp((values(k) - b) / (a - b), 0.0, 1.0);
  return first - 0.5 + covered;
}

// A line u = slope * v + offset fitted to (v, u) points.
struct ImageLine {
  double slope = 0.0;
  double offset = 0.0;
};

ImageLine fit_line(const std::vector<Eigen::Vector2d>& vu) {
  Eigen::MatrixXd a(vu.size(), 2);
  Eigen::VectorXd b(vu.size());
  for (std::size_t i = 0; i < vu.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << vu[i].x(), 1.0;
    b(static_cast<Eigen::Index>(i)) = vu[i].y();
  }
  const Eigen::Vector2d x = a.colPivHouseholderQr().solve(b);
  return {x(0), x(1)};
}

// The inner edge (the side towards the car) of a solid lane line at `lateral` (from the centre
// line, left positive [m]; the paint spans lateral +-0.075 m), measured row by row where the road
// is 5-10 m ahead, and the line fitted to it. The search follows the model's projection of the
// edge within +-3 px.
ImageLine measured_inner_edge(const Shot& shot, double lateral) {
  const RoadStation station = shot.world.road.station_at(kCarX);
  const double inner = lateral > 0.0 ? lateral - 0.075 : lateral + 0.075;
  std::vector<Eigen::Vector2d> points;
  const auto near = shot.project(station.surface_point(inner) + 5.0 * station.forward);
  const auto far = shot.project(station.surface_point(inner) + 10.0 * station.forward);
  if (!near || !far) return {};
  for (int v = static_cast<int>(std::ceil(far->y())); v <= static_cast<int>(near->y()); ++v) {
    const double share = (v - far->y()) / (near->y() - far->y());
    const int u = static_cast<int>(std::lround(far->x() + share * (near->x() - far->x())));
    if (u < 4 || u + 4 >= shot.intrinsics.width) continue;
    // Paint on the outer side: from the image centre, outwards.
    const double edge = step_edge(u - 3, u + 3, [&](int k) { return shot.light(k, v, 1); });
    points.emplace_back(v, edge);
  }
  EXPECT_GE(points.size(), 15u) << "lateral " << lateral;
  return fit_line(points);
}

// The vanishing point of the road from its two edge lines.
Eigen::Vector2d measured_road_vanishing_point(const Shot& shot) {
  const CrossSection& section = shot.world.road.segment_at(kCarX).section;
  const double edge = section.edge_line - 0.075;  // the lines' centres
  const ImageLine left = measured_inner_edge(shot, edge);
  const ImageLine right = measured_inner_edge(shot, -edge);
  const double v = (right.offset - left.offset) / (left.slope - right.slope);
  return {left.slope * v + left.offset, v};
}

// The row where sky meets ground in column u (blue: bright sky, dark grass), within the rows
// [top, bottom] [pixels].
double measured_horizon_row(const Shot& shot, int u, int top, int bottom) {
  int v = top;
  while (v < bottom && shot.light(u, v, 2) > 0.3) ++v;
  return step_edge(v - 3, v + 3, [&](int k) { return shot.light(u, k, 2); });
}

// ---- tests -------------------------------------------------------------------------------------

TEST(CameraRender, StraightRoadLaneEdgesMeetAtTheRoadsVanishingPoint) {
  const Shot shot = render_shot(bare_street(), camera_mounting(0.0, 1.0, -2.0));
  const Eigen::Vector2d expected = shot.vanishing_point(Eigen::Vector3d::UnitX());
  const Eigen::Vector2d measured = measured_road_vanishing_point(shot);
  EXPECT_NEAR(measured.x(), expected.x(), 0.5);
  EXPECT_NEAR(measured.y(), expected.y(), 0.5);
}

// DESIGN §1 / docs/conventions.md: pitch > 0 turns the nose down, yaw > 0 to the left.
TEST(CameraRender, PitchedDownSeesTheVanishingPointAboveTheCentre) {
  const Shot shot = render_shot(bare_street(), camera_mounting(0.0, 3.0, 0.0));
  const Eigen::Vector2d vp = measured_road_vanishing_point(shot);
  EXPECT_LT(vp.y(), shot.intrinsics.cy - 8.0);  // 200 px x tan(3 deg) = 10.5 px above
  EXPECT_NEAR(vp.x(), shot.intrinsics.cx, 1.0);
}

TEST(CameraRender, YawedLeftSeesTheVanishingPointRightOfTheCentre) {
  const Shot shot = render_shot(bare_street(), camera_mounting(0.0, 0.0, 3.0));
  const Eigen::Vector2d vp = measured_road_vanishing_point(shot);
  EXPECT_GT(vp.x(), shot.intrinsics.cx + 8.0);
  EXPECT_NEAR(vp.y(), shot.intrinsics.cy, 1.0);
}

// Roll > 0 raises the camera's left side (docs/conventions.md): the level horizon then rises to
// the right in the image (v falls as u grows), by the roll angle.
TEST(CameraRender, RolledSeesTheHorizonRiseToTheRight) {
  const double roll_deg = 3.0;
  const Shot shot = render_shot(bare_street(), camera_mounting(roll_deg, 0.0, 0.0));
  const int left = 60, right = shot.intrinsics.width - 61;
  const double v_left = measured_horizon_row(shot, left, 40, 160);
  const double v_right = measured_horizon_row(shot, right, 40, 160);
  EXPECT_LT(v_right, v_left);
  const double tilt_deg = deg_from_rad(std::atan2(v_left - v_right, right - left));
  EXPECT_NEAR(tilt_deg, roll_deg, 0.2);
}

// A box 20 m ahead on the right, 5 m tall, against the sky.
World street_with_box() {
  World world = bare_street();
  WorldObject box;
  box.id = static_cast<std::uint32_t>(world.objects.size());
  box.kind = ObjectKind::kGuardRailPost;  // a plain box
  box.material = standard_material(Surface::kMetal);
  box.world_from_object.translation() = Eigen::Vector3d(kCarX + 20.0, -6.0, 0.0);
  box.size = Eigen::Vector3d(2.0, 2.0, 5.0);
  world.objects.push_back(box);
  return world;
}

// The image point of the 3-D segment from `a` to `b` whose coordinate `axis` (0: u, 1: v) is
// `value`, by bisection along the segment (its image is monotonic in that coordinate).
Eigen::Vector2d point_on_image_of(const Shot& shot, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, int axis, double value) {
  double lo = 0.0, hi = 1.0;
  const bool rising = (*shot.project(b))(axis) > (*shot.project(a))(axis);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const bool below = (*shot.project(a + mid * (b - a)))(axis) < value;
    (below == rising ? lo : hi) = mid;
  }
  return *shot.project(a + lo * (b - a));
}

struct EdgeResiduals {
  int count = 0;
  double worst = 0.0;  // [px]
  double mean = 0.0;   // signed [px]
};

// The box's edges measured in the image against the camera model's projection of its 3-D edges:
// its left edge (the back vertical edge of its left face) row by row, its top edge (the front
// face's) column by column.
std::array<EdgeResiduals, 2> box_edge_residuals(const Shot& shot) {
  std::array<EdgeResiduals, 2> result;
  const Eigen::Vector3d bottom(kCarX + 21.0, -5.0, 2.0), top(kCarX + 21.0, -5.0, 5.0);
  const Eigen::Vector3d left(kCarX + 19.0, -5.0, 5.0), right(kCarX + 19.0, -7.0, 5.0);
  for (int axis = 0; axis < 2; ++axis) {
    // axis 0: the vertical edge, rows; axis 1: the top edge, columns.
    const Eigen::Vector3d& a = axis == 0 ? bottom : left;
    const Eigen::Vector3d& b = axis == 0 ? top : right;
    const int along = 1 - axis;
    const double from = std::min((*shot.project(a))(along), (*shot.project(b))(along)) + 2.0;
    const double to = std::max((*shot.project(a))(along), (*shot.project(b))(along)) - 2.0;
    EdgeResiduals& r = result[static_cast<std::size_t>(axis)];
    for (int k = static_cast<int>(std::ceil(from)); k < to; ++k) {
      const double expected = point_on_image_of(shot, a, b, along, k)(axis);
      const int centre = static_cast<int>(std::lround(expected));
      const double measured = step_edge(centre - 3, centre + 3, [&](int m) {
        return axis == 0 ? shot.light(m, k, 2) : shot.light(k, m, 2);
      });
      r.worst = std::max(r.worst, std::abs(measured - expected));
      r.mean += measured - expected;
      ++r.count;
    }
    if (r.count > 0) r.mean /= r.count;
  }
  return result;
}

TEST(CameraRender, BoxEdgesLandWhereTheCameraModelProjectsThem) {
  const Shot shot = render_shot(street_with_box(), camera_mounting(0.0, 0.0, 0.0));
  for (const EdgeResiduals& r : box_edge_residuals(shot)) {
    ASSERT_GE(r.count, 10);
    EXPECT_LT(r.worst, 0.5);
    EXPECT_LT(std::abs(r.mean), 0.25);
  }
}

// The same through a barrel-distorted lens (plumb_bob): the edges bend, and lie on the model's
// distorted projection.
TEST(CameraRender, DistortedBoxEdgesLandWhereTheCameraModelProjectsThem) {
  core::CameraIntrinsics distorted = wide_camera();
  distorted.distortion_model = core::DistortionModel::kPlumbBob;
  distorted.distortion_coefficients = {-0.2, 0.04, 0.001, -0.002, 0.0};
  const Shot shot =
      render_shot(street_with_box(), camera_mounting(0.0, 0.0, 0.0), clean_options(), distorted);
  for (const EdgeResiduals& r : box_edge_residuals(shot)) {
    ASSERT_GE(r.count, 10);
    EXPECT_LT(r.worst, 0.5);
    EXPECT_LT(std::abs(r.mean), 0.25);
  }
  // The distortion moved the box by pixels: the test would see a pinhole render.
  const Eigen::Vector3d corner(kCarX + 19.0, -7.0, 5.0);
  const Shot pinhole{shot.world, shot.states, wide_camera(), shot.vehicle_from_camera, {}};
  EXPECT_GT((*shot.project(corner) - *pinhole.project(corner)).norm(), 3.0);
}

TEST(CameraRender, SameArgumentsGiveTheSameBytes) {
  CameraRenderOptions options;  // noise, vignetting and shadows on
  options.motion_blur_samples = 2;
  const World world = bare_street();
  const VehicleStates states = standing_car();
  const WorldScene scene(world);
  const CameraRenderer camera(scene, states, camera_mounting(1.0, 2.0, 3.0), wide_camera(), options,
                              11);
  const auto png = encode_image(camera.render(3), CameraImageFormat::kPng);
  EXPECT_EQ(encode_image(camera.render(3), CameraImageFormat::kPng), png);
  // Another frame has other noise.
  EXPECT_NE(encode_image(camera.render(4), CameraImageFormat::kPng), png);
}

TEST(CameraRender, EdgePixelsAreSupersampled) {
  // Without anti-aliasing the pixels across a lane line's edge are asphalt or paint; with it, the
  // pixels the edge crosses are in between.
  CameraRenderOptions options = clean_options();
  options.supersampling = 1;
  const Shot sharp = render_shot(bare_street(), camera_mounting(0.0, 0.0, 0.0), options);
  const Shot smooth = render_shot(bare_street(), camera_mounting(0.0, 0.0, 0.0));
  const RoadStation station = sharp.world.road.station_at(kCarX);
  const double inner = 0.15 - sharp.world.road.segment_at(kCarX).section.edge_line;
  auto mixed = [&](const Shot& shot) {
    int count = 0;
    for (double ahead = 5.0; ahead < 10.0; ahead += 0.25) {
      const Eigen::Vector2d p =
          *shot.project(station.surface_point(inner) + ahead * station.forward);
      const int v = static_cast<int>(std::lround(p.y()));
      for (int u = static_cast<int>(p.x()) - 3; u <= static_cast<int>(p.x()) + 3; ++u) {
        const double green = shot.light(u, v, 1);
        count += green > 0.15 && green < 0.5 ? 1 : 0;  // between asphalt (~0.04) and paint (~0.8)
      }
    }
    return count;
  };
  EXPECT_EQ(mixed(sharp), 0);
  EXPECT_GE(mixed(smooth), 5);
}

TEST(CameraShading, TheAsphaltHasTextureAtTheScaleATrackerFollows) {
  // A feature tracker (the camera's motion estimator) needs corners on the road at the scale of
  // its window: 21 px are 20-40 cm of road at 5-15 m ahead of a KITTI camera. A road whose tone
  // changes only over metres (patches) and below a pixel (grain) offers none. So squares of 30 cm
  // (which average the grain away) must differ from their neighbours by a few per cent of the tone:
  // 7.2 % RMS here; 1.6 % before the asphalt had stains and stones.
  const World world = bare_street();
  const auto asphalt = std::find_if(world.objects.begin(), world.objects.end(), [](const auto& o) {
    return o.kind == ObjectKind::kRoad && o.material.surface == Surface::kAsphalt;
  });
  ASSERT_NE(asphalt, world.objects.end());
  SurfaceHit hit;
  hit.object_id = asphalt->id;
  hit.surface = Surface::kAsphalt;
  hit.normal = Eigen::Vector3f::UnitZ();
  constexpr double kSquare = 0.3, kStep = 0.01;  // [m]
  auto square_tone = [&](double x0, double y0) {
    double sum = 0.0;
    int count = 0;
    for (double x = x0; x < x0 + kSquare; x += kStep) {
      for (double y = y0; y < y0 + kSquare; y += kStep) {
        sum += surface_look(world, hit, Eigen::Vector3d(x, y, 0.0)).albedo.y();
        ++count;
      }
    }
    return sum / count;
  };
  double squared_change = 0.0, tone = 0.0;
  int pairs = 0;
  for (double x = 100.0; x < 130.0; x += 2.0 * kSquare) {
    for (double y = -1.5; y < 1.5; y += 2.0 * kSquare) {
      const double here = square_tone(x, y), ahead = square_tone(x + kSquare, y);
      squared_change += (ahead - here) * (ahead - here);
      tone += here;
      ++pairs;
    }
  }
  const double relative_change = std::sqrt(squared_change / pairs) / (tone / pairs);
  EXPECT_GT(relative_change, 0.04)
      << "neighbouring 30 cm squares differ by " << 100.0 * relative_change << " % (RMS)";
}

TEST(CameraRenderOptions, CheckNamesTheOffendingField) {
  CameraRenderOptions options;
  options.supersampling = 0;
  EXPECT_THAT([&] { options.Check(); }, ::testing::ThrowsMessage<std::invalid_argument>(
                                            ::testing::HasSubstr("supersampling")));
  options = {};
  options.vignetting = 1.0;
  EXPECT_THAT([&] { options.Check(); },
              ::testing::ThrowsMessage<std::invalid_argument>(::testing::HasSubstr("vignetting")));
}

TEST(OpticalRayTable, InterpolatesThePinholeExactly) {
  const core::CameraIntrinsics intrinsics = wide_camera();
  const OpticalRayTable table(intrinsics);
  for (const Eigen::Vector2d& pixel : {Eigen::Vector2d(0.25, 0.75), Eigen::Vector2d(-0.4, 199.3),
                                       Eigen::Vector2d(320.1, 50.6), Eigen::Vector2d(639.4, 3.0)}) {
    const Eigen::Vector3f ray = table.at(pixel.x(), pixel.y());
    const Eigen::Vector3d expected = core::pixel_to_ray(intrinsics, pixel);
    EXPECT_LT((ray.cast<double>() - expected).norm(), 1e-6) << pixel.transpose();
  }
}

TEST(OpticalRayTable, InterpolatesADistortedLensWithinAHundredthOfAPixel) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("dashcam_wide");
  const OpticalRayTable table(intrinsics);
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(0.25, 0.75), Eigen::Vector2d(1279.4, 719.3), Eigen::Vector2d(640.1, 360.6),
        Eigen::Vector2d(100.5, 600.5)}) {
    const Eigen::Vector3d ray = table.at(pixel.x(), pixel.y()).cast<double>().normalized();
    const Eigen::Vector3d expected = core::pixel_to_ray(intrinsics, pixel);
    // The angle between the rays, in pixels at fx.
    EXPECT_LT(std::acos(std::min(1.0, ray.dot(expected))) * intrinsics.fx, 0.01)
        << pixel.transpose();
  }
}

}  // namespace
}  // namespace x2car::sim
