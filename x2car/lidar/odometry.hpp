// LiDAR odometry: ICP against a local voxel map, in the style of KISS-ICP (Vizzo et al.,
// "KISS-ICP: In Defense of Point-to-Point ICP", RA-L 2023), giving the poses that the LiDAR
// calibrator levels and compares with the car's track (DESIGN §2, issue 5). One departure:
// points on planar patches use the point-to-plane residual (registration.hpp says why).
//
// Per sweep (register_sweep):
//   1. drop NaN/inf points (counted) and those outside [min_range_m, max_range_m];
//   2. downsample to voxel_size * 0.5 (the points for the map), in the same pass;
//   3. deskew those: with per-point times, move every point to the sensor frame at the middle of
//      the sweep's time span, along the constant twist of the last two poses (se3.hpp), then
//      downsample again to voxel_size * 1.5 for the registration. Deskewing after the first
//      downsampling moves a third of the points for the same result: which point stands for a
//      voxel hardly depends on a few centimetres of skew;
//   4. predict the pose with constant velocity and align the sweep to the map (registration.hpp)
//      within 3 sigma of the adaptive threshold (adaptive_threshold.hpp), robust kernel scale
//      kernel_scale_factor * sigma;
//   5. judge the result (RegistrationStatus); a failed one keeps the prediction as the pose;
//   6. add the sweep to the map and drop voxels beyond max_range_m from the sensor.
// The world frame is the LiDAR frame of the first sweep at its reference time. Buffers, the map
// and the downsampling tables live in the engine and are reused: after the first sweeps, a sweep
// allocates only when it or the map is larger than any before.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "x2car/io/point_cloud.hpp"
#include "x2car/lidar/adaptive_threshold.hpp"
#include "x2car/lidar/planar_normals.hpp"
#include "x2car/lidar/se3.hpp"
#include "x2car/lidar/voxel_downsample.hpp"
#include "x2car/lidar/voxel_map.hpp"

namespace x2car::lidar {

struct OdometryOptions {
  // Range window of the points used [m]: beyond max_range_m returns are sparse and noisy; within
  // min_range_m they may be the car itself. max_range_m is also the local map's radius.
  double max_range_m = 100.0;  // KISS-ICP's default
  double min_range_m = 2.0;
  // Map voxel edge [m] (KISS-ICP: max_range / 100). The sweep is downsampled at half of it for the
  // map and at 1.5 times it for the registration.
  double voxel_size_m = 1.0;
  int max_points_per_voxel = 20;  // KISS-ICP's default
  // Adaptive threshold: sigma before any correction has been measured [m], and the smallest
  // correction counted [m] (KISS-ICP: 2.0 and 0.1). Correspondences are searched within 3 sigma.
  double initial_threshold_m = 2.0;
  double min_motion_m = 0.1;
  // Geman-McClure scale as a share of sigma (KISS-ICP: sigma / 3).
  double kernel_scale_factor = 1.0 / 3.0;
  // Weight of point-to-point terms (points off planar patches) against point-to-plane ones
  // (registration.hpp). 1 treats them alike; on simulated urban drives (64 beams, 12 s) drift was
  // 0.03 % at 0.1 and 0.3, but at 1 without deskewing the odometry froze at a standstill start.
  double point_to_point_weight = 0.1;
  // Gauss-Newton iterations per sweep (KISS-ICP: 500). Most sweeps need 5-12; a few at turns of
  // the 32-beam drives needed 50-100, and stopping them at 50 let a wrong prediction in.
  int max_iterations = 100;
  // Stop when the update's norm (metres and radians) is below this. KISS-ICP uses 1e-4; on the
  // simulated urban drives 1e-3 gives the same drift (64 beams: 0.022 %) in half the iterations.
  double convergence = 1e-3;
  // After max_iterations, a registration still moving by more than this per iteration has not
  // converged; one creeping by less (millimetre steps as nearest neighbours swap) is accepted.
  double max_final_update = 1e-2;
  bool deskew = true;  // used only when the sweep has per-point times
  // Per-point times spanning more than this are not trusted (another unit, or broken): the sweep
  // is then taken as it is, not deskewed [s].
  double max_sweep_span_s = 1.0;
  // A registration needs at least this many downsampled points and correspondences.
  std::size_t min_points = 100;
  // Degeneracy (registration.hpp, constraint_strength): the weakest direction of translation or
  // rotation must hold at least this share of the surfaces' information (0 .. 1/3), judged from
  // up to degeneracy_samples points. A single plane scores 0; the weakest sweeps of simulated
  // 60 s urban drives scored 0.03 (64 beams) and 0.06 (32 and 128 beams).
  double min_translation_constraint = 0.01;
  double min_rotation_constraint = 0.01;
  std::size_t degeneracy_samples = 1000;
  // Which registered points count as on a planar patch (point-to-plane terms; planar_normals.hpp).
  PlanarityOptions planarity;
  // Motions no car makes between two sweeps: the registration failed [m/s], [rad/s].
  double max_speed_mps = 70.0;
  double max_angular_rate = 3.0;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

enum class RegistrationStatus {
  kFirstSweep,         // the map was empty: this sweep starts it (the pose is the prediction)
  kOk,                 // aligned; the pose is the registration's
  kTooFewPoints,       // too few points or correspondences; the pose is the prediction
  kNotConverged,       // still moving after max_iterations, or a singular system; prediction
  kDegenerate,         // the surfaces leave a direction free (a plane, a tunnel); prediction
  kImplausibleMotion,  // faster than max_speed_mps or max_angular_rate; prediction
};

std::string to_string(RegistrationStatus status);  // "first_sweep", "ok", ...

struct OdometryStep {
  // Time the pose refers to [s]: sweep_time + deskew_time_s.
  double time = 0.0;
  // The LiDAR's pose; world = the first sweep's LiDAR frame at its reference time.
  Eigen::Isometry3d world_from_lidar = Eigen::Isometry3d::Identity();
  RegistrationStatus status = RegistrationStatus::kFirstSweep;
  int iterations = 0;
  std::size_t points_used = 0;  // correspondences in the last iteration
  double threshold_m = 0.0;     // correspondence distance used (3 sigma) [m]
  double rms_residual_m = 0.0;  // of the correspondences (normal distance on planes) [m]

  // Within-sweep time the points were deskewed to [s]: the middle of the span of their `t`, or 0
  // when the sweep has no per-point time or they span more than max_sweep_span_s (then nothing
  // is deskewed).
  double deskew_time_s = 0.0;
  bool deskewed = false;           // false also for the first two sweeps (no velocity yet)
  std::size_t invalid_points = 0;  // NaN or infinite coordinates, skipped
  std::size_t points_in_range = 0;
  std::size_t source_points = 0;        // after downsampling, registered
  double translation_constraint = 0.0;  // see OdometryOptions::min_translation_constraint
  double rotation_constraint = 0.0;
};

class LidarOdometry {
 public:
  explicit LidarOdometry(const OdometryOptions& options = {});  // calls options.Check()

  // Registers one sweep. `sweep.points` are in the LiDAR frame, with `t` per point when
  // `sweep.has_time`; `sweep_time` [s] is the time `t` counts from, and must increase from sweep
  // to sweep (std::invalid_argument otherwise).
  OdometryStep register_sweep(const io::PointCloud& sweep, double sweep_time);

  const OdometryOptions& options() const { return options_; }
  std::size_t sweeps() const { return sweeps_; }
  const VoxelHashMap& map() const { return map_; }

 private:
  // Steps 1 to 3 into frame_; fills the point counts and deskew fields of `step`.
  void preprocess(const io::PointCloud& sweep, OdometryStep& step);
  Eigen::Isometry3d predict(double time) const;  // constant velocity from the last two poses
  RegistrationStatus judge(const OdometryStep& step, double last_update,
                           const Eigen::Isometry3d& estimate) const;

  OdometryOptions options_;
  VoxelHashMap map_;
  AdaptiveThreshold threshold_;
  VoxelDownsampler fine_downsampler_;    // voxel_size / 2: the sweep for the map
  VoxelDownsampler coarse_downsampler_;  // voxel_size * 1.5: the sweep for the registration
  std::size_t sweeps_ = 0;
  // The constant-velocity model: the last pose, its time, and the twist from the pose before it.
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  double last_time_ = 0.0;
  Vector6d twist_per_second_ = Vector6d::Zero();  // body frame, [m/s] and [rad/s]
  // Reused buffers.
  std::vector<Eigen::Vector3f> frame_;          // downsampled for the map, deskewed
  std::vector<float> frame_times_;              // their within-sweep times [s]
  std::vector<Eigen::Vector3f> source_;         // downsampled for the registration
  std::vector<std::uint32_t> source_of_frame_;  // index in source_ of each frame_ point's voxel
  std::vector<PatchMoments> moments_;
  std::vector<Eigen::Vector3f> source_normals_;              // zero where the patch is not planar
  std::vector<VoxelHashMap::Neighbourhood> neighbourhoods_;  // registration's lookup cache
};

}  // namespace x2car::lidar
