#include "x2car/core/options_check.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

using ::testing::HasSubstr;

constexpr double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::nan("");

// The message a failing check throws; empty when it passes.
template <typename Call>
std::string message_of(Call call) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return {};
}

TEST(OptionsCheck, OneMessageStyleNamesStructFieldRuleAndValue) {
  const OptionsCheck check("LidarCalibrationOptions");
  EXPECT_EQ(message_of([&] { check.at_least("ground_every", 0, 1); }),
            "LidarCalibrationOptions.ground_every must be >= 1 (got 0)");
  EXPECT_EQ(message_of([&] { check.positive("block_s", -2.5); }),
            "LidarCalibrationOptions.block_s must be > 0 and finite (got -2.5)");
  EXPECT_EQ(message_of([&] { check.in_range("share", 1.5, 0.0, 1.0, Bounds::kOpenMin); }),
            "LidarCalibrationOptions.share must be in (0, 1] (got 1.5)");
  EXPECT_EQ(message_of([&] { check.ordered("min_gap_m", 5.0, "max_gap_m", 3.0); }),
            "LidarCalibrationOptions.min_gap_m must be <= LidarCalibrationOptions.max_gap_m "
            "(got 5 > 3)");
  EXPECT_EQ(message_of([&] { check.that(false, "beams", "must be 32, 64 or 128", 16); }),
            "LidarCalibrationOptions.beams must be 32, 64 or 128 (got 16)");
  EXPECT_EQ(message_of([&] { check.that(false, "lengths_m", "must not be empty"); }),
            "LidarCalibrationOptions.lengths_m must not be empty");
}

TEST(OptionsCheck, HugeAndTinyNumbersPrintCompactly) {
  const OptionsCheck check("X");
  const std::string huge = message_of([&] { check.at_most("f", 1.7e308, 10.0); });
  EXPECT_THAT(huge, HasSubstr("(got 1.7e+308)"));
  EXPECT_LT(huge.size(), 40u) << huge;
  EXPECT_THAT(message_of([&] { check.positive("f", -1e-300); }), HasSubstr("(got -1e-300)"));
}

TEST(OptionsCheck, NanFailsEveryCheckAndInfinityOnlyWhereAllowed) {
  const OptionsCheck check("X");
  for (const double bad : {kNaN, kInf, -kInf}) {
    EXPECT_THROW(check.finite("f", bad), std::invalid_argument);
    EXPECT_THROW(check.positive("f", bad), std::invalid_argument);
    EXPECT_THROW(check.non_negative("f", bad), std::invalid_argument);
    EXPECT_THROW(check.in_range("f", bad, 0.0, 1.0), std::invalid_argument);
    EXPECT_THROW(check.ordered("a", bad, "b", 1.0), std::invalid_argument);
    EXPECT_THROW(check.ordered("a", 0.0, "b", bad), std::invalid_argument);
  }
  EXPECT_THROW(check.at_least("f", kNaN, 0.0), std::invalid_argument);
  EXPECT_THROW(check.at_most("f", kNaN, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(check.at_least("f", kInf, 0.0));
  EXPECT_NO_THROW(check.at_most("f", -kInf, 0.0));
}

TEST(OptionsCheck, BoundsIncludeTheEndsTheySay) {
  const OptionsCheck check("X");
  EXPECT_NO_THROW(check.in_range("f", 0.0, 0.0, 1.0));
  EXPECT_NO_THROW(check.in_range("f", 1.0, 0.0, 1.0));
  EXPECT_THROW(check.in_range("f", 0.0, 0.0, 1.0, Bounds::kOpen), std::invalid_argument);
  EXPECT_THROW(check.in_range("f", 1.0, 0.0, 1.0, Bounds::kOpen), std::invalid_argument);
  EXPECT_THROW(check.in_range("f", 0.0, 0.0, 1.0, Bounds::kOpenMin), std::invalid_argument);
  EXPECT_NO_THROW(check.in_range("f", 1.0, 0.0, 1.0, Bounds::kOpenMin));
  EXPECT_NO_THROW(check.in_range("f", 0.0, 0.0, 1.0, Bounds::kOpenMax));
  EXPECT_THROW(check.in_range("f", 1.0, 0.0, 1.0, Bounds::kOpenMax), std::invalid_argument);
  EXPECT_NO_THROW(check.positive("f", 1e-300));
  EXPECT_THROW(check.positive("f", 0.0), std::invalid_argument);
  EXPECT_NO_THROW(check.non_negative("f", 0.0));
  EXPECT_NO_THROW(check.ordered("a", 2.0, "b", 2.0));
  EXPECT_NO_THROW(check.probability("p", 1.0));
  EXPECT_THROW(check.probability("p", -0.1), std::invalid_argument);
}

TEST(OptionsCheck, EachAngleIsCheckedAndNamed) {
  const OptionsCheck check("FilterOptions");
  EXPECT_NO_THROW(check.non_negative("floor", EulerAngles{0.0, 0.1, 0.2}));
  EXPECT_THAT(message_of([&] {
                check.non_negative("floor", EulerAngles{0.1, -0.1, 0.1});
              }),
              HasSubstr("FilterOptions.floor.pitch must be >= 0 and finite"));
  EXPECT_THAT(message_of([&] {
                check.non_negative("floor", EulerAngles{0.1, 0.1, kNaN});
              }),
              HasSubstr("FilterOptions.floor.yaw"));
  EXPECT_THAT(message_of([&] {
                check.non_negative("floor", EulerAngles{kInf, 0.1, 0.1});
              }),
              HasSubstr("FilterOptions.floor.roll"));
}

}  // namespace
}  // namespace x2car
