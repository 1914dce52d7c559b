#include "x2car/lidar/voxel_downsample.hpp"

#include <algorithm>
#include <stdexcept>

#include "x2car/lidar/voxel_key.hpp"

namespace x2car::lidar {

std::size_t VoxelDownsampler::find_slot(std::uint64_t key) const {
  const std::size_t mask = slots_.size() - 1;
  std::size_t slot = voxel_hash(key, bits_);
  while (slots_[slot].generation == generation_ && slots_[slot].key != key) {
    slot = (slot + 1) & mask;
  }
  return slot;
}

void VoxelDownsampler::grow() {
  std::vector<Slot> old = std::move(slots_);
  bits_ = std::max(bits_ + 1, 12);
  slots_.assign(std::size_t{1} << bits_, Slot{});
  const std::uint32_t generation = generation_;
  generation_ = 1;
  for (const Slot& slot : old) {
    if (slot.generation == generation) slots_[find_slot(slot.key)] = Slot{slot.key, 1, slot.kept};
  }
}

void VoxelDownsampler::start(float voxel_size) {
  if (!(voxel_size > 0.0f)) throw std::invalid_argument("voxel_size must be > 0");
  inverse_size_ = 1.0f / voxel_size;
  kept_ = 0;
  if (slots_.empty()) grow();
  if (++generation_ == 0) {  // wrapped: old stamps could alias the new generation
    std::ranges::fill(slots_, Slot{});
    generation_ = 1;
  }
}

std::pair<const VoxelDownsampler::Slot*, bool> VoxelDownsampler::insert(
    const Eigen::Vector3f& point) {
  const std::uint64_t key = voxel_key(voxel_index(point, inverse_size_));
  std::size_t slot = find_slot(key);
  if (slots_[slot].generation == generation_) return {&slots_[slot], false};
  // At most half full, so that probe sequences stay short.
  if (2 * (std::size_t{kept_} + 1) > slots_.size()) {
    grow();
    slot = find_slot(key);
  }
  slots_[slot] = Slot{key, generation_, kept_++};
  return {&slots_[slot], true};
}

void VoxelDownsampler::downsample(std::span<const Eigen::Vector3f> points, float voxel_size,
                                  std::vector<Eigen::Vector3f>& kept,
                                  std::vector<std::uint32_t>* kept_index,
                                  std::vector<std::uint32_t>* kept_from) {
  start(voxel_size);
  kept.clear();
  if (kept_index != nullptr) kept_index->clear();
  if (kept_from != nullptr) kept_from->clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [slot, first] = insert(points[i]);
    if (first) {
      kept.push_back(points[i]);
      if (kept_from != nullptr) kept_from->push_back(static_cast<std::uint32_t>(i));
    }
    if (kept_index != nullptr) kept_index->push_back(slot->kept);
  }
}

}  // namespace x2car::lidar
