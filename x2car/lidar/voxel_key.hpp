// Integer voxel coordinates packed into one 64-bit key, and the hash the odometry's flat tables
// use. 21 bits per axis hold +-2^20 voxels: +-1048 km at 1 m voxels, more than any drive.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace x2car::lidar {

constexpr std::int32_t kVoxelKeyOffset = 1 << 20;
constexpr std::uint64_t kVoxelKeyMask = (std::uint64_t{1} << 21) - 1;

inline std::uint64_t voxel_key(const Eigen::Vector3i& index) {
  return (static_cast<std::uint64_t>(index.x() + kVoxelKeyOffset) & kVoxelKeyMask) |
         (static_cast<std::uint64_t>(index.y() + kVoxelKeyOffset) & kVoxelKeyMask) << 21 |
         (static_cast<std::uint64_t>(index.z() + kVoxelKeyOffset) & kVoxelKeyMask) << 42;
}

inline Eigen::Vector3i voxel_index_from_key(std::uint64_t key) {
  return {static_cast<std::int32_t>(key & kVoxelKeyMask) - kVoxelKeyOffset,
          static_cast<std::int32_t>((key >> 21) & kVoxelKeyMask) - kVoxelKeyOffset,
          static_cast<std::int32_t>((key >> 42) & kVoxelKeyMask) - kVoxelKeyOffset};
}

// The voxel holding `point`, for voxels of edge 1 / inverse_size.
inline Eigen::Vector3i voxel_index(const Eigen::Vector3f& point, float inverse_size) {
  return {static_cast<std::int32_t>(std::floor(point.x() * inverse_size)),
          static_cast<std::int32_t>(std::floor(point.y() * inverse_size)),
          static_cast<std::int32_t>(std::floor(point.z() * inverse_size))};
}

// Fibonacci hashing: the top `bits` bits of key * 2^64/phi spread neighbouring voxels apart.
inline std::size_t voxel_hash(std::uint64_t key, int bits) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - bits));
}

}  // namespace x2car::lidar
