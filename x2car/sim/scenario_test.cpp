#include "x2car/sim/scenario.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace x2car::sim {
namespace {

TEST(Scenario, NamesRoundTrip) {
  for (const Scenario scenario : {Scenario::kStraight, Scenario::kUrban, Scenario::kHighway,
                                  Scenario::kMixed, Scenario::kCity}) {
    EXPECT_EQ(scenario_from_string(to_string(scenario)), scenario);
  }
  EXPECT_EQ(scenario_names(),
            (std::vector<std::string>{"straight", "urban", "highway", "mixed", "city"}));
  EXPECT_EQ(to_string(Scenario::kHighway), "highway");
}

TEST(Scenario, UnknownNameListsTheValidOnes) {
  try {
    scenario_from_string("rural");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("'rural'"));
    EXPECT_THAT(error.what(), ::testing::HasSubstr("straight, urban, highway, mixed, city"));
  }
}

}  // namespace
}  // namespace x2car::sim
