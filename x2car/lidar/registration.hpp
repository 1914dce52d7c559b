// ICP of a downsampled sweep against the voxel map (KISS-ICP, Vizzo et al. 2023, Sec. III-E):
// Gauss-Newton on the Geman-McClure robust cost, correspondences within a distance, the pose
// updated on the left by the exponential of the solved twist.
//
// Points on planar patches use the point-to-plane residual n^T (q - m) instead of point-to-point
// (as GenZ-ICP, Lee et al. 2024, mixes the two). Why: a spinning LiDAR samples a plane the car
// slides along (the road, a facade beside it) in the same pattern in every sweep, so the
// point-to-point nearest neighbours of a sweep are the previous sweeps' samples of the same beam
// and column, which pull the estimate back to "no motion"; on the simulator this froze the
// odometry of a car pulling away from a stop. The normal component carries no such pull. Points
// off planes (poles, trees, edges, a far ring of road) keep point-to-point terms, down-weighted
// (IcpSettings::point_to_point_weight) because they carry the same pull.
// Association and the normal equations run in one TBB parallel_deterministic_reduce over the
// points; the per-thread partial sums are a few dozen doubles, so an iteration allocates nothing.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <span>

#include "x2car/lidar/voxel_map.hpp"

namespace x2car::lidar {

struct IcpSettings {
  double max_correspondence_distance = 1.0;  // [m]
  double kernel_scale = 0.3;                 // Geman-McClure scale kappa [m]
  // Weight of the point-to-point terms (points off planes) against the point-to-plane ones.
  double point_to_point_weight = 0.1;
  int max_iterations = 100;
  double convergence = 1e-4;  // stop when the update's norm (metres and radians) is below this

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct IcpResult {
  Eigen::Isometry3d world_from_source = Eigen::Isometry3d::Identity();
  int iterations = 0;
  bool converged = false;  // the update fell below `convergence`, or cycled between two states
  // Norm of the last update (metres and radians); infinite when the system could not be solved.
  double last_update = std::numeric_limits<double>::infinity();
  std::size_t correspondences = 0;  // in the last iteration
  double rms_residual = 0.0;        // of those correspondences [m]
};

// Aligns `source` (sensor frame) to `map` from `initial_guess` (world_from_source).
// `source_normals` is empty or holds a unit normal (sensor frame) per source point where its
// neighbourhood is planar and zero elsewhere. Stops early, unconverged, when an iteration finds
// fewer than 6 correspondences or a singular system. `neighbourhoods` (one per source point, reset
// by the caller) is scratch space that saves the map lookups of later iterations. Throws
// std::invalid_argument on bad settings (IcpSettings::Check).
IcpResult align_to_map(std::span<const Eigen::Vector3f> source,
                       std::span<const Eigen::Vector3f> source_normals, const VoxelHashMap& map,
                       const Eigen::Isometry3d& initial_guess, const IcpSettings& settings,
                       std::span<VoxelHashMap::Neighbourhood> neighbourhoods);

// How well the map's surfaces around the aligned `source` pin down each direction of motion
// (the point-to-plane information, which point-to-point ICP's own normal equations do not show:
// on a single plane they stay well conditioned while the pose slides freely). From up to
// `max_samples` source points spread over the sweep, the voxel of each one's nearest map point
// gives a local shape: a plane constrains its normal n (n n^T), a line the two directions across it
// ((I - d d^T) / 2); scattered voxels are skipped. Both figures are the smallest eigenvalue of the
// mean of those terms, 0 (a direction free) to 1/3 (all directions alike): translation from the
// normals, rotation from u x n with u the unit direction of the point from the sensor.
struct ConstraintStrength {
  double translation = 0.0;
  double rotation = 0.0;
  std::size_t shaped_voxels = 0;  // samples that landed in a planar or linear voxel
};

ConstraintStrength constraint_strength(std::span<const Eigen::Vector3f> source,
                                       const VoxelHashMap& map,
                                       const Eigen::Isometry3d& world_from_source,
                                       std::size_t max_samples);

}  // namespace x2car::lidar
