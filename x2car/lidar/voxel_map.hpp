// The odometry's local map (KISS-ICP, Vizzo et al. 2023, Sec. III-D): a hash of voxels, each
// holding up to a fixed number of world points, dropped once they are farther from the sensor than
// the map's radius. Points are stored as float: a 60 s drive spans < 1 km, where float keeps
// < 0.1 mm; a drive of tens of kilometres would keep ~1 mm.
//
// Flat storage, built for the registration's inner loop: an open-addressing table (linear
// probing, at most half full, backward-shift deletion so that no tombstones build up) maps a voxel
// key to a block index; blocks are packed at the front of three arrays (key, count, points), and a
// dropped block is replaced by the last one. Lookups are a hash, a probe or two and one contiguous
// block of points. Memory grows to the largest map seen and is then reused.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace x2car::lidar {

class VoxelHashMap {
 public:
  // voxel_size [m] > 0; max_points_per_voxel in [1, 65535]. A point closer than
  // voxel_size / sqrt(max_points_per_voxel) to one already in its voxel is not added (as
  // KISS-ICP 1.0 does): the voxel's points then spread over its surface instead of piling up
  // where the car stood still or where each sweep's beams return to the same spots.
  VoxelHashMap(float voxel_size, int max_points_per_voxel);

  float voxel_size() const { return voxel_size_; }
  bool empty() const { return block_keys_.empty(); }
  std::size_t voxel_count() const { return block_keys_.size(); }
  std::size_t point_count() const;

  void clear();

  // Adds world points to their voxels, skipping those whose voxel is full.
  void add_points(std::span<const Eigen::Vector3f> points_in_world);

  // Drops the voxels whose centre is farther than `max_distance` [m] from `centre_in_world`.
  void remove_far_from(const Eigen::Vector3f& centre_in_world, float max_distance);

  // The map point closest to `query` among the 2x2x2 voxels around the voxel corner nearest to
  // it. That block covers every point within voxel_size / 2 of `query`, so the answer is the true
  // nearest neighbour whenever that is closer than voxel_size / 2 (the correspondences that
  // matter once the registration has converged), and a near point otherwise: 8 lookups instead of
  // the 27 of a 3x3x3 search. Returns false when those voxels are empty.
  bool closest_point(const Eigen::Vector3f& query, Eigen::Vector3f& closest,
                     float& distance2) const;

  // The blocks of the 2x2x2 voxels last searched for one query point. The registration keeps one
  // per point: once it has nearly converged a point stays by the same grid corner from iteration
  // to iteration, and the eight hash lookups become one comparison. Valid while the map is not
  // changed (it points into the map's storage); reset it (Neighbourhood{}) after.
  struct Neighbourhood {
    std::uint64_t corner_key = ~std::uint64_t{0};
    int voxels = 0;  // non-empty ones among the 8, first in the arrays
    std::array<const Eigen::Vector3f*, 8> points{};
    std::array<std::uint16_t, 8> counts{};
  };
  bool closest_point(const Eigen::Vector3f& query, Eigen::Vector3f& closest, float& distance2,
                     Neighbourhood& cache) const;

  // The points of the voxel holding `point` (empty when none).
  std::span<const Eigen::Vector3f> voxel_points(const Eigen::Vector3f& point) const;

 private:
  static constexpr std::uint64_t kEmptyKey = ~std::uint64_t{0};  // no valid key has all 64 bits
  struct Slot {
    std::uint64_t key = kEmptyKey;
    std::uint32_t block = 0;
  };

  // Slot holding `key`, or the empty slot where it would go.
  std::size_t find_slot(std::uint64_t key) const;
  std::uint32_t find_block(std::uint64_t key) const;  // kNoBlock when absent
  void erase_slot(std::size_t slot);
  void grow_table();

  static constexpr std::uint32_t kNoBlock = ~std::uint32_t{0};
  float voxel_size_;
  float inverse_voxel_size_;
  float min_point_distance2_;  // [m^2]
  std::size_t points_per_voxel_;
  int bits_ = 0;
  std::vector<Slot> slots_;
  std::vector<std::uint64_t> block_keys_;
  std::vector<std::uint16_t> block_counts_;
  std::vector<Eigen::Vector3f> block_points_;  // points_per_voxel_ per block
};

}  // namespace x2car::lidar
