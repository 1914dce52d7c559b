#include "x2car/lidar/voxel_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace x2car::lidar {
namespace {

TEST(VoxelHashMap, ClosestPointMatchesBruteForceAfterRemovals) {
  // A jittered 0.5 m lattice: 8 points per voxel, never two closer than the map's crowding limit
  // (1 / sqrt(20) = 0.22 m), so that every point is kept.
  std::mt19937 random(7);
  std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
  std::vector<Eigen::Vector3f> points;
  for (int i = -20; i < 20; ++i) {
    for (int j = -20; j < 20; ++j) {
      for (int k = -20; k < 20; ++k) {
        points.emplace_back(0.5f * static_cast<float>(i) + 0.25f + jitter(random),
                            0.5f * static_cast<float>(j) + 0.25f + jitter(random),
                            0.5f * static_cast<float>(k) + 0.25f + jitter(random));
      }
    }
  }
  VoxelHashMap map(1.0f, 20);
  map.add_points(points);
  EXPECT_EQ(map.point_count(), points.size());
  map.add_points(points);  // the same points again are all too close to their twins
  EXPECT_EQ(map.point_count(), points.size());
  // Drop everything farther than 7 m from (2, 0, 0), then check every lookup still works.
  const Eigen::Vector3f centre(2.0f, 0.0f, 0.0f);
  map.remove_far_from(centre, 7.0f);
  std::vector<Eigen::Vector3f> remaining;
  for (const auto& p : points) {
    const Eigen::Vector3f voxel_centre = p.array().floor() + 0.5f;
    if ((voxel_centre - centre).norm() <= 7.0f) remaining.push_back(p);
  }
  EXPECT_EQ(map.point_count(), remaining.size());
  EXPECT_LT(remaining.size(), points.size() / 2);
  std::uniform_real_distribution<float> coordinate(-6.0f, 8.0f);
  int exact = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3f query(coordinate(random), coordinate(random) - 2.0f,
                                coordinate(random) - 2.0f);
    float best = std::numeric_limits<float>::infinity();
    for (const auto& p : remaining) best = std::min(best, (p - query).squaredNorm());
    Eigen::Vector3f closest;
    float distance2 = 0.0f;
    VoxelHashMap::Neighbourhood cache;
    const bool found = map.closest_point(query, closest, distance2, cache);
    // Exact whenever the true neighbour is within half a voxel; never closer than the truth.
    if (best < 0.25f) {
      ASSERT_TRUE(found);
      EXPECT_FLOAT_EQ(distance2, best);
      ++exact;
    }
    if (found) {
      EXPECT_GE(distance2, best * (1.0f - 1e-6f));  // to rounding
    }
    // A second query through the cache gives the same answer.
    float again = 0.0f;
    map.closest_point(query, closest, again, cache);
    EXPECT_EQ(again, distance2);
  }
  EXPECT_GT(exact, 1000);
}

}  // namespace
}  // namespace x2car::lidar
