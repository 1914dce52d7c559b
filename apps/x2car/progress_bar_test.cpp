#include "apps/x2car/progress_bar.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

namespace x2car::cli {
namespace {

TEST(ProgressBar, DrawsTheFinalStateAndEndsTheLine) {
  std::ostringstream stream;
  {
    ProgressBar bar("odometry", stream);
    const auto report = bar.callback();
    for (std::size_t i = 0; i <= 50; ++i) report(i, 50);
  }
  const std::string text = stream.str();
  EXPECT_THAT(text, ::testing::HasSubstr("odometry ["));
  EXPECT_THAT(text, ::testing::HasSubstr("] 50/50"));
  EXPECT_EQ(text.back(), '\n');
  // Throttled: 51 updates within a few microseconds draw the first and the last state only.
  EXPECT_EQ(std::count(text.begin(), text.end(), '\r'), 2);
}

TEST(ProgressBar, DisabledBarDrawsNothing) {
  ProgressBar bar("quiet", /*enabled=*/false);
  EXPECT_FALSE(bar.active());
  bar.update(1, 2);  // must not crash or print
}

}  // namespace
}  // namespace x2car::cli
