// Voxel downsampling (KISS-ICP, Vizzo et al. 2023, Sec. III-B): one point per occupied voxel, the
// first one met, so that dense near-range surfaces do not outweigh far ones and the registration
// sees a few thousand points instead of ~100 k.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace x2car::lidar {

// Holds its hash table between calls, so that downsampling sweep after sweep allocates only when
// a sweep has more voxels than any before it. The table is sized by the voxels kept (at most half
// full), not by the points, so that it stays small enough for the cache.
class VoxelDownsampler {
 public:
  // Writes into `kept` (cleared first) the first point of `points` in each voxel of edge
  // `voxel_size` [m] (> 0), in input order. When `kept_index` is given, it receives for every
  // input point the index in `kept` of its voxel's point; when `kept_from` is given, it receives
  // for every kept point its index in `points`.
  void downsample(std::span<const Eigen::Vector3f> points, float voxel_size,
                  std::vector<Eigen::Vector3f>& kept,
                  std::vector<std::uint32_t>* kept_index = nullptr,
                  std::vector<std::uint32_t>* kept_from = nullptr);

  // The same one point at a time, for callers that filter as they go: start(), then keep(p) for
  // each point in order, which says whether p is the first of its voxel.
  void start(float voxel_size);
  bool keep(const Eigen::Vector3f& point) { return insert(point).second; }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t generation = 0;  // the slot is taken in this call when it equals generation_
    std::uint32_t kept = 0;        // index of the voxel's point in `kept`
  };
  std::size_t find_slot(std::uint64_t key) const;  // holding `key`, or free in this generation
  void grow();                                     // doubles the table and re-inserts
  // The point's slot, and whether the point is the first of its voxel in this generation.
  std::pair<const Slot*, bool> insert(const Eigen::Vector3f& point);

  std::vector<Slot> slots_;  // open addressing, linear probing; size a power of two
  int bits_ = 0;
  std::uint32_t generation_ = 0;  // bumped per call, so that the table never needs clearing
  std::uint32_t kept_ = 0;        // voxels kept in this generation
  float inverse_size_ = 1.0f;
};

}  // namespace x2car::lidar
