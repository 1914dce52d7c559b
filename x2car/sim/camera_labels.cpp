#include "x2car/sim/camera_labels.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/sim/camera_model.hpp"

namespace x2car::sim {
namespace {

constexpr double kMinDirectionZ = 1e-9;   // a VP needs the direction in front of the camera
constexpr double kMinLineNormal = 1e-12;  // [1/px]: below it the horizon is at infinity

// Whether the road ahead of arc length s is straight and level (CameraLabelOptions).
void road_flags(const RoadLayout& road, double s, const CameraLabelOptions& options,
                CameraFrameLabel& label) {
  const RoadStation here = road.station_at(s);
  double max_curvature = 0.0, max_grade_change = 0.0, max_crossfall_change = 0.0;
  RoadStation previous = here;
  const int steps =
      std::max(1, static_cast<int>(std::ceil(options.lookahead_m / options.sample_step_m)));
  const double step = options.lookahead_m / steps;
  for (int i = 1; i <= steps; ++i) {
    const RoadStation next = road.station_at(s + i * step);
    // The road's own curvature from its heading (not the route's: a lane change bends the car's
    // path, not the lane edges).
    const double turn = wrap_angle(next.heading_enu() - previous.heading_enu());
    max_curvature = std::max(max_curvature, std::abs(turn) / step);
    max_grade_change = std::max(max_grade_change, std::abs(next.grade - here.grade));
    max_crossfall_change =
        std::max(max_crossfall_change, std::abs(next.crossfall - here.crossfall));
    previous = next;
  }
  label.straight = max_curvature <= options.max_curvature;
  label.level = max_grade_change <= options.max_grade_change &&
                max_crossfall_change <= options.max_crossfall_change;
}

void append(std::string& row, double value) {
  row += ',';
  row += io::format_number(value);
}

void append_vp(std::string& row, const std::optional<VanishingPoint>& vp) {
  if (!vp) {
    row += ",,,,";
    return;
  }
  append(row, vp->undistorted_px.x());
  append(row, vp->undistorted_px.y());
  if (vp->distorted_px) {
    append(row, vp->distorted_px->x());
    append(row, vp->distorted_px->y());
  } else {
    row += ",,";
  }
}

void append_horizon(std::string& row, const std::optional<HorizonLine>& horizon) {
  if (!horizon) {
    row += ",,,,,";
    return;
  }
  append(row, horizon->angle);
  append(row, horizon->offset_px);
  for (int i = 0; i < 3; ++i) append(row, horizon->line[i]);
}

}  // namespace

void CameraLabelOptions::Check() const {
  const OptionsCheck check("CameraLabelOptions");
  check.positive("lookahead_m", lookahead_m);
  check.positive("sample_step_m", sample_step_m);
  check.non_negative("max_curvature", max_curvature);
  check.non_negative("max_grade_change", max_grade_change);
  check.non_negative("max_crossfall_change", max_crossfall_change);
}

std::optional<VanishingPoint> vanishing_point(const core::CameraIntrinsics& intrinsics,
                                              const Eigen::Vector3d& direction_optical) {
  const Eigen::Vector3d d = direction_optical.normalized();
  if (!(d.z() > kMinDirectionZ)) return std::nullopt;
  VanishingPoint vp;
  vp.undistorted_px = {intrinsics.fx * d.x() / d.z() + intrinsics.cx,
                       intrinsics.fy * d.y() / d.z() + intrinsics.cy};
  if (!vp.undistorted_px.allFinite()) return std::nullopt;
  vp.distorted_px = core::project_to_pixel(intrinsics, d);
  return vp;
}

std::optional<HorizonLine> horizon_line(const core::CameraIntrinsics& intrinsics,
                                        const Eigen::Vector3d& up_normal_optical) {
  // l = K^-T n: pixels p with l . p = 0 have rays n . K^-1 p = 0, parallel to the plane.
  const Eigen::Vector3d n = up_normal_optical.normalized();
  Eigen::Vector3d line(
      n.x() / intrinsics.fx, n.y() / intrinsics.fy,
      n.z() - intrinsics.cx * n.x() / intrinsics.fx - intrinsics.cy * n.y() / intrinsics.fy);
  const double scale = line.head<2>().norm();
  if (!(scale > kMinLineNormal) || !line.allFinite()) return std::nullopt;
  HorizonLine horizon;
  horizon.line = line / scale;
  const double a = horizon.line.x(), b = horizon.line.y();
  // Direction (-b, a); on screen v points down, so counter-clockwise is atan2(-dv, du).
  horizon.angle = wrap_angle(std::atan2(-a, -b));
  horizon.offset_px = -(a * intrinsics.cx + b * intrinsics.cy + horizon.line.z());
  return horizon;
}

CameraFrameLabel camera_frame_label(const core::CameraIntrinsics& intrinsics,
                                    const Eigen::Isometry3d& vehicle_from_camera,
                                    const VehicleState& state, const RoadLayout& road,
                                    const CameraLabelOptions& options) {
  options.Check();
  CameraFrameLabel label;
  label.time = state.time;
  label.speed_mps = state.speed;
  label.yaw_rate = state.yaw_rate;
  const Eigen::Matrix3d vehicle_from_optical =
      vehicle_from_camera.linear() * camera_body_from_optical();
  const Eigen::Matrix3d optical_from_world =
      world_from_camera_optical(state.world_from_vehicle, vehicle_from_camera).linear().transpose();

  // The road at the car: its tangent with the grade, and the surface's normal (road_layout.hpp).
  const RoadStation station = road.station_at(state.arc_length);
  const Eigen::Matrix3d world_from_road = station.surface_rotation();
  label.forward_vp =
      vanishing_point(intrinsics, vehicle_from_optical.transpose() * Eigen::Vector3d::UnitX());
  label.road_vp = vanishing_point(intrinsics, optical_from_world * world_from_road.col(0));
  label.road_horizon = horizon_line(intrinsics, optical_from_world * world_from_road.col(2));
  label.level_horizon = horizon_line(intrinsics, optical_from_world * Eigen::Vector3d::UnitZ());
  road_flags(road, state.arc_length, options, label);
  return label;
}

std::string format_camera_labels_csv_header() {
  std::string header = "time,speed_mps,yaw_rate,straight,level";
  for (const char* vp : {"forward_vp", "road_vp"}) {
    header += fmt::format(",{0}_u,{0}_v,{0}_u_distorted,{0}_v_distorted", vp);
  }
  for (const char* horizon : {"road_horizon", "level_horizon"}) {
    header += fmt::format(",{0}_angle,{0}_offset_px,{0}_a,{0}_b,{0}_c", horizon);
  }
  return header + "\n";
}

std::string format_camera_label_row(const CameraFrameLabel& label) {
  std::string row = io::format_number(label.time);
  append(row, label.speed_mps);
  append(row, label.yaw_rate);
  row += label.straight ? ",1" : ",0";
  row += label.level ? ",1" : ",0";
  append_vp(row, label.forward_vp);
  append_vp(row, label.road_vp);
  append_horizon(row, label.road_horizon);
  append_horizon(row, label.level_horizon);
  return row + "\n";
}

}  // namespace x2car::sim
