#include "x2car/lidar/voxel_map.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "x2car/lidar/voxel_key.hpp"

namespace x2car::lidar {

VoxelHashMap::VoxelHashMap(float voxel_size, int max_points_per_voxel)
    : voxel_size_(voxel_size),
      inverse_voxel_size_(1.0f / voxel_size),
      min_point_distance2_(voxel_size * voxel_size / static_cast<float>(max_points_per_voxel)),
      points_per_voxel_(static_cast<std::size_t>(max_points_per_voxel)) {
  if (!(voxel_size > 0.0f)) throw std::invalid_argument("voxel_size must be > 0");
  if (max_points_per_voxel < 1 || max_points_per_voxel > 65535) {
    throw std::invalid_argument("max_points_per_voxel must be in [1, 65535]");
  }
  bits_ = 12;
  slots_.assign(std::size_t{1} << bits_, Slot{});
}

std::size_t VoxelHashMap::point_count() const {
  std::size_t count = 0;
  for (const std::uint16_t n : block_counts_) count += n;
  return count;
}

void VoxelHashMap::clear() {
  std::fill(slots_.begin(), slots_.end(), Slot{});
  block_keys_.clear();
  block_counts_.clear();
  block_points_.clear();
}

std::size_t VoxelHashMap::find_slot(std::uint64_t key) const {
  const std::size_t mask = slots_.size() - 1;
  std::size_t slot = voxel_hash(key, bits_);
  while (slots_[slot].key != key && slots_[slot].key != kEmptyKey) slot = (slot + 1) & mask;
  return slot;
}

std::uint32_t VoxelHashMap::find_block(std::uint64_t key) const {
  const Slot& slot = slots_[find_slot(key)];
  return slot.key == key ? slot.block : kNoBlock;
}

void VoxelHashMap::grow_table() {
  ++bits_;
  slots_.assign(std::size_t{1} << bits_, Slot{});
  for (std::uint32_t block = 0; block < block_keys_.size(); ++block) {
    slots_[find_slot(block_keys_[block])] = Slot{block_keys_[block], block};
  }
}

void VoxelHashMap::add_points(std::span<const Eigen::Vector3f> points_in_world) {
  for (const Eigen::Vector3f& point : points_in_world) {
    const std::uint64_t key = voxel_key(voxel_index(point, inverse_voxel_size_));
    std::size_t slot = find_slot(key);
    if (slots_[slot].key == kEmptyKey) {
      if (2 * (block_keys_.size() + 1) > slots_.size()) {
        grow_table();
        slot = find_slot(key);
      }
      slots_[slot] = Slot{key, static_cast<std::uint32_t>(block_keys_.size())};
      block_keys_.push_back(key);
      block_counts_.push_back(0);
      block_points_.resize(block_points_.size() + points_per_voxel_);
    }
    const std::uint32_t block = slots_[slot].block;
    std::uint16_t& count = block_counts_[block];
    if (count >= points_per_voxel_) continue;
    Eigen::Vector3f* points = block_points_.data() + block * points_per_voxel_;
    const bool crowded = std::any_of(points, points + count, [&](const Eigen::Vector3f& p) {
      return (p - point).squaredNorm() < min_point_distance2_;
    });
    if (!crowded) points[count++] = point;
  }
}

// Backward-shift deletion (Knuth, TAOCP vol. 3, 6.4 Algorithm R): entries after the hole move
// into it unless their home slot lies cyclically in (hole, entry], which keeps every probe
// sequence unbroken without tombstones.
void VoxelHashMap::erase_slot(std::size_t hole) {
  const std::size_t mask = slots_.size() - 1;
  std::size_t next = hole;
  while (true) {
    slots_[hole] = Slot{};
    while (true) {
      next = (next + 1) & mask;
      if (slots_[next].key == kEmptyKey) return;
      const std::size_t home = voxel_hash(slots_[next].key, bits_);
      const bool stays =
          hole <= next ? (hole < home && home <= next) : (hole < home || home <= next);
      if (!stays) break;
    }
    slots_[hole] = slots_[next];
    hole = next;
  }
}

void VoxelHashMap::remove_far_from(const Eigen::Vector3f& centre_in_world, float max_distance) {
  const float max_distance2 = max_distance * max_distance;
  std::size_t block = 0;
  while (block < block_keys_.size()) {
    const Eigen::Vector3f voxel_centre =
        (voxel_index_from_key(block_keys_[block]).cast<float>().array() + 0.5f) * voxel_size_;
    if ((voxel_centre - centre_in_world).squaredNorm() <= max_distance2) {
      ++block;
      continue;
    }
    erase_slot(find_slot(block_keys_[block]));
    // Move the last block into the hole and point its slot at the new place.
    const std::size_t last = block_keys_.size() - 1;
    if (block != last) {
      block_keys_[block] = block_keys_[last];
      block_counts_[block] = block_counts_[last];
      std::copy_n(block_points_.begin() + static_cast<std::ptrdiff_t>(last * points_per_voxel_),
                  points_per_voxel_,
                  block_points_.begin() + static_cast<std::ptrdiff_t>(block * points_per_voxel_));
      slots_[find_slot(block_keys_[block])].block = static_cast<std::uint32_t>(block);
    }
    block_keys_.pop_back();
    block_counts_.pop_back();
    block_points_.resize(block_points_.size() - points_per_voxel_);
  }
}

bool VoxelHashMap::closest_point(const Eigen::Vector3f& query, Eigen::Vector3f& closest,
                                 float& distance2) const {
  Neighbourhood cache;
  return closest_point(query, closest, distance2, cache);
}

bool VoxelHashMap::closest_point(const Eigen::Vector3f& query, Eigen::Vector3f& closest,
                                 float& distance2, Neighbourhood& cache) const {
  // The voxels i0 and i0 + 1 on each axis share the grid corner nearest to the query.
  const Eigen::Vector3i i0 =
      voxel_index((query.array() * inverse_voxel_size_ - 0.5f).matrix(), 1.0f);
  const std::uint64_t corner_key = voxel_key(i0);
  if (cache.corner_key != corner_key) {
    cache.corner_key = corner_key;
    cache.voxels = 0;
    for (int dx = 0; dx < 2; ++dx) {
      for (int dy = 0; dy < 2; ++dy) {
        for (int dz = 0; dz < 2; ++dz) {
          const std::uint32_t block = find_block(voxel_key(i0 + Eigen::Vector3i(dx, dy, dz)));
          if (block == kNoBlock) continue;
          cache.points[cache.voxels] = block_points_.data() + block * points_per_voxel_;
          cache.counts[cache.voxels] = block_counts_[block];
          ++cache.voxels;
        }
      }
    }
  }
  // Locals, so that the compiler keeps them in registers (`distance2` might alias the points).
  float best_distance2 = std::numeric_limits<float>::infinity();
  const Eigen::Vector3f* best = nullptr;
  const float qx = query.x(), qy = query.y(), qz = query.z();
  for (int v = 0; v < cache.voxels; ++v) {
    const Eigen::Vector3f* points = cache.points[v];
    const int count = cache.counts[v];
    for (int k = 0; k < count; ++k) {
      const float dx = points[k].x() - qx, dy = points[k].y() - qy, dz = points[k].z() - qz;
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best_distance2) {
        best_distance2 = d2;
        best = points + k;
      }
    }
  }
  distance2 = best_distance2;
  if (best != nullptr) closest = *best;
  return distance2 < std::numeric_limits<float>::infinity();
}

std::span<const Eigen::Vector3f> VoxelHashMap::voxel_points(const Eigen::Vector3f& point) const {
  const std::uint32_t block = find_block(voxel_key(voxel_index(point, inverse_voxel_size_)));
  if (block == kNoBlock) return {};
  return {block_points_.data() + block * points_per_voxel_, block_counts_[block]};
}

}  // namespace x2car::lidar
