// Odometry drift as the KITTI odometry benchmark measures it (Geiger et al. 2012, devkit
// evaluate_odometry): for every start pose (every `step`-th) and every path length L, the first
// pose at least L further along the ground-truth path closes a segment; the segment's error is
// the relative pose error E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j), with translation error |t_E| / L
// and rotation error angle(R_E) / L. Averaged over all segments of all lengths.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <span>
#include <vector>

namespace x2car::lidar {

struct DriftOptions {
  std::vector<double> lengths_m = {50.0, 100.0, 200.0, 400.0};  // segment lengths [m]
  std::size_t step = 10;  // start a segment at every step-th pose (KITTI: 10, 1 s at 10 Hz)

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct DriftAtLength {
  double length_m = 0.0;
  std::size_t segments = 0;
  double translation_percent = 0.0;    // mean |t_E| / L x 100 [%]; NaN when segments == 0
  double rotation_deg_per_100m = 0.0;  // mean angle(R_E) / L [deg / 100 m]; NaN when none
};

struct Drift {
  std::size_t segments = 0;  // over all lengths; 0 when the path is shorter than every length
  double translation_percent = 0.0;    // [%]; NaN when segments == 0
  double rotation_deg_per_100m = 0.0;  // [deg / 100 m]; NaN when segments == 0
  std::vector<DriftAtLength> per_length;
  double path_length_m = 0.0;  // of the ground truth
};

// `estimate` and `truth` hold the same poses' world_from_sensor, in the same order (each in its
// own world frame: only relative poses are compared). Throws std::invalid_argument when their sizes
// differ.
Drift relative_drift(std::span<const Eigen::Isometry3d> estimate,
                     std::span<const Eigen::Isometry3d> truth, const DriftOptions& options = {});

}  // namespace x2car::lidar
