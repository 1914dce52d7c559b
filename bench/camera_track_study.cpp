// The motion estimator's tracks against the simulated world (docs/methods.md, camera §1a): for a
// drive that `x2car simulate --sensors ins,camera` wrote with the default camera, each corner the
// tracker follows between two frames is also cast as a ray into the world in the first frame's pose
// and projected into the second's: its true position. The two are consecutive frames, the pair the
// calibrator makes at the default camera's 10 Hz (at other rates it pairs frames 0.1 s apart,
// CameraCalibrationOptions::motion_frame_step). Printed, over the straight frames at 3 m/s or more:
//   - the tracks' error (median |error|, median along the true flow, share over 1 px) by what the
//     corner lies on (asphalt, paint, curb, sidewalk, grass, ...) and by side (left or right of
//     the principal point);
//   - the road plane's horizon against the labels' (median, median absolute deviation [deg]) from
//     the tracks, tracked once and again through the homography (RoadPlaneMotionOptions::prewarp),
//     from those of the second tracking that lie on asphalt or paint (road corners) or on asphalt
//     alone, and from the corners' true positions (what perfect tracks would give);
//   - from the same tracks, the vertical position of the travel's vanishing point against the
//     labels' road VP [px] (the pitch `auto` averages; docs/methods.md camera §3).
//   x2car_camera_track_study SCENARIO SEED DURATION_S DRIVE [MAX_LATERAL_OVER_HEIGHT]
// MAX_LATERAL_OVER_HEIGHT replaces RoadPlaneMotionOptions::max_lateral_over_height (the wedge).
// SCENARIO, SEED and DURATION_S must be those the drive was simulated with (the world is made again
// from them). Movers are left out of the rays: corners on traffic count as errors.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "x2car/camera/road_plane_motion.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/sim/camera_labels.hpp"
#include "x2car/sim/camera_render.hpp"
#include "x2car/sim/camera_writer.hpp"
#include "x2car/sim/simulation.hpp"
#include "x2car/sim/world_scene.hpp"

namespace {

using namespace x2car;

struct TrackErrors {
  std::vector<double> along_flow_px;
  std::vector<double> size_px;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    fmt::print(stderr,
               "usage: x2car_camera_track_study SCENARIO SEED DURATION_S DRIVE "
               "[MAX_LATERAL_OVER_HEIGHT]\n");
    return 2;
  }
  sim::SimulationOptions options;
  options.scenario = sim::scenario_from_string(argv[1]);
  options.seed = std::strtoull(argv[2], nullptr, 10);
  options.duration_s = std::atof(argv[3]);
  options.sensors = {"ins", "camera"};
  const std::string drive = argv[4];
  camera::RoadPlaneMotionOptions motion_defaults;
  if (argc == 6) motion_defaults.max_lateral_over_height = std::atof(argv[5]);
  const sim::Simulation simulation = sim::simulate(options);
  const core::CameraIntrinsics& intrinsics = *simulation.camera;
  const Eigen::Isometry3d vehicle_from_camera =
      simulation.truth.vehicle_from_sensor.at("camera").vehicle_from_sensor();
  const sim::WorldScene scene(simulation.world);
  const sim::CameraRenderer camera(scene, simulation.states, vehicle_from_camera, intrinsics,
                                   options.camera_render, 1);
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  std::map<std::string, TrackErrors> errors;
  std::map<std::string, std::vector<double>> horizon_errors_deg;
  std::map<std::string, std::vector<double>> travel_v_errors_px;
  for (std::size_t index = 1; index < camera.frame_count(); ++index) {
    const double time0 = camera.frame_time(index - 1);
    const double time1 = camera.frame_time(index);
    const sim::VehicleState state = sim::vehicle_state_at(simulation.states, time1);
    const sim::CameraFrameLabel label =
        sim::camera_frame_label(intrinsics, vehicle_from_camera, state, simulation.world.road);
    if (!label.straight || state.speed < 3.0 || !label.road_horizon) continue;
    std::vector<cv::Mat> frames;
    for (const std::size_t frame : {index - 1, index}) {
      frames.push_back(cv::imread(fmt::format("{}/camera/images/{:010d}.png", drive, frame),
                                  cv::IMREAD_GRAYSCALE));
    }
    const Eigen::Isometry3d pose0 = camera.world_from_camera_optical(time0);
    const Eigen::Isometry3d pose1 = camera.world_from_camera_optical(time1);
    const double road_horizon = camera::horizon_angle(label.road_horizon->line);
    for (const bool prewarp : {false, true}) {
      camera::RoadPlaneMotionOptions motion = motion_defaults;
      motion.prewarp = prewarp;
      const camera::RoadTracks tracks = camera::road_plane_tracks(frames, intrinsics, motion);
      std::vector<Eigen::Vector3f> directions;
      for (const Eigen::Vector2d& pixel : tracks.oldest_px) {
        directions.push_back(
            (pose0.linear() * (camera_matrix.inverse() * pixel.homogeneous()).normalized())
                .cast<float>());
      }
      std::vector<sim::SurfaceHit> hits(directions.size());
      scene.trace_surfaces(pose0.translation(), directions, 300.0f, nullptr, hits);
      camera::RoadTracks true_tracks, road_only_tracks, asphalt_tracks;
      for (std::size_t i = 0; i < hits.size(); ++i) {
        if (!std::isfinite(hits[i].range)) continue;
        const Eigen::Vector3d point =
            pose0.translation() + static_cast<double>(hits[i].range) * directions[i].cast<double>();
        const Eigen::Vector3d seen = camera_matrix * (pose1.inverse() * point);
        const Eigen::Vector2d truth = seen.head<2>() / seen.z();
        true_tracks.oldest_px.push_back(tracks.oldest_px[i]);
        true_tracks.current_px.push_back(truth);
        const Eigen::Vector2d error = tracks.current_px[i] - truth;
        const Eigen::Vector2d flow = truth - tracks.oldest_px[i];
        // In sim::Surface's order.
        static constexpr const char* kSurfaceNames[] = {
            "asphalt", "paint", "curb",   "sidewalk", "grass", "facade", "metal",
            "sign",    "bark",  "leaves", "car",      "glass", "tyre",   "clothing"};
        static_assert(std::size(kSurfaceNames) ==
                      static_cast<std::size_t>(sim::Surface::kClothing) + 1);
        const std::string surface = kSurfaceNames[static_cast<std::size_t>(hits[i].surface)];
        const std::string side = tracks.oldest_px[i].x() < intrinsics.cx ? "left" : "right";
        if (hits[i].surface == sim::Surface::kAsphalt ||
            hits[i].surface == sim::Surface::kLanePaint) {
          road_only_tracks.oldest_px.push_back(tracks.oldest_px[i]);
          road_only_tracks.current_px.push_back(tracks.current_px[i]);
        }
        if (hits[i].surface == sim::Surface::kAsphalt) {
          asphalt_tracks.oldest_px.push_back(tracks.oldest_px[i]);
          asphalt_tracks.current_px.push_back(tracks.current_px[i]);
        }
        for (const std::string& key : {surface, surface + " " + side}) {
          TrackErrors& bucket = errors[(prewarp ? "again  " : "once   ") + key];
          bucket.size_px.push_back(error.norm());
          bucket.along_flow_px.push_back(flow.norm() > 0.1 ? error.dot(flow.normalized()) : 0.0);
        }
      }
      // The road plane from `some` tracks, recorded under `key`: its horizon against the labels'
      // [deg] and its travel's vanishing point against the labels' road VP [px].
      const auto record_plane = [&](const camera::RoadTracks& some, const std::string& key) {
        const camera::FrameEstimate estimate =
            camera::road_plane_from_tracks(some.oldest_px, some.current_px, intrinsics, motion);
        if (!estimate.usable()) return;
        horizon_errors_deg[key].push_back(
            deg_from_rad(camera::horizon_angle(estimate.horizon_line) - road_horizon));
        if (label.road_vp) {
          travel_v_errors_px[key].push_back(estimate.road_vanishing_point_px.y() -
                                            label.road_vp->undistorted_px.y());
        }
      };
      record_plane(tracks, prewarp ? "tracked again" : "tracked once");
      if (prewarp) {
        record_plane(true_tracks, "true positions");
        record_plane(road_only_tracks, "road corners");
        record_plane(asphalt_tracks, "asphalt corners");
      }
    }
  }
  fmt::print("tracks against the world's true image motion [px]\n");
  for (const auto& [key, bucket] : errors) {
    const double over =
        static_cast<double>(std::count_if(bucket.size_px.begin(), bucket.size_px.end(),
                                          [](double e) { return e > 1.0; })) /
        static_cast<double>(bucket.size_px.size());
    fmt::print(
        "  {:<20} {:6} tracks  median |error| {:.2f}  along the flow {:+.2f}  over 1 px {:.0f} %\n",
        key, bucket.size_px.size(), median(bucket.size_px), median(bucket.along_flow_px),
        100.0 * over);
  }
  const auto print_medians = [](const std::string& title,
                                const std::map<std::string, std::vector<double>>& by_key) {
    fmt::print("{}\n", title);
    for (const auto& [key, values] : by_key) {
      fmt::print("  {:<15} {:4} frames  median {:+.3f}  median absolute deviation {:.3f}\n", key,
                 values.size(), median(values), median_absolute_deviation(values));
    }
  };
  print_medians("road plane's horizon against the labels' [deg]", horizon_errors_deg);
  print_medians("travel's vanishing point v against the labels' road VP [px]", travel_v_errors_px);
  return 0;
}
