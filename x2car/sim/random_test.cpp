#include "x2car/sim/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "x2car/core/robust_stats.hpp"

namespace x2car::sim {
namespace {

TEST(Random, RawStreamIsTheStandardMt19937_64) {
  Random random(5489);  // the standard's default seed; [rand.predef] fixes the 10000th output
  std::uint64_t value = 0;
  for (int i = 0; i < 10000; ++i) value = random.next();
  EXPECT_EQ(value, 9981545732273789042ULL);
}

TEST(Random, UniformAndNormalHaveTheirMoments) {
  Random random(123);
  std::vector<double> u, z;
  for (int i = 0; i < 200000; ++i) {
    u.push_back(random.uniform(-2.0, 3.0));
    z.push_back(random.normal(1.5, 0.2));
  }
  EXPECT_GE(*std::min_element(u.begin(), u.end()), -2.0);
  EXPECT_LT(*std::max_element(u.begin(), u.end()), 3.0);
  EXPECT_NEAR(weighted_mean(u), 0.5, 0.02);
  EXPECT_NEAR(standard_deviation(u), 5.0 / std::sqrt(12.0), 0.01);
  EXPECT_NEAR(weighted_mean(z), 1.5, 0.002);
  EXPECT_NEAR(standard_deviation(z), 0.2, 0.002);
  EXPECT_EQ(random.normal(4.0, 0.0), 4.0);
  EXPECT_THROW(random.normal(0.0, -1.0), std::invalid_argument);
  EXPECT_THROW(random.uniform(1.0, 0.0), std::invalid_argument);
}

TEST(Random, DerivedSeedsAreDistinctAndStable) {
  EXPECT_EQ(Random::derive_seed(1, 2), Random::derive_seed(1, 2));
  EXPECT_NE(Random::derive_seed(1, 2), Random::derive_seed(1, 3));
  EXPECT_NE(Random::derive_seed(1, 2), Random::derive_seed(2, 2));
}

}  // namespace
}  // namespace x2car::sim
