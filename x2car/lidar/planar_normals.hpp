// Normals of the planar patches a downsampled sweep's points sit on, for the point-to-plane terms
// of the registration (registration.hpp). Each registered point stands for a voxel of the sweep;
// the finer-downsampled points of that voxel give its shape by their covariance: a plane when the
// smallest spread is far below the middle one and the middle one shows a real second extent (a
// single ring's arc across a voxel of far road is a line, not a plane, and gets no normal).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace x2car::lidar {

struct PlanarityOptions {
  std::size_t min_points = 4;  // fine points in the voxel
  float max_flatness = 0.1f;   // smallest / middle eigenvalue of the covariance
  float min_extent_m = 0.1f;   // standard deviation along the middle direction [m]

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// Moments of the fine points per registered point; kept between sweeps to avoid allocating.
struct PatchMoments {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();        // of offsets from the kept point
  Eigen::Matrix3f outer_sum = Eigen::Matrix3f::Zero();  // of their outer products
  std::uint32_t count = 0;
};

// normals[i] = unit normal of the patch around coarse[i], or zero where it is not planar.
// `voxel_of_fine[k]` is the index in `coarse` of the voxel of fine[k] (VoxelDownsampler).
void planar_normals(std::span<const Eigen::Vector3f> fine,
                    std::span<const std::uint32_t> voxel_of_fine,
                    std::span<const Eigen::Vector3f> coarse, const PlanarityOptions& options,
                    std::vector<PatchMoments>& moments, std::vector<Eigen::Vector3f>& normals);

}  // namespace x2car::lidar
