#include "x2car/report/series_decimation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace x2car::report {
namespace {

Series ramp_with_spike(std::size_t count, std::size_t spike_at) {
  Series series{"heading_offset", "rad", {}, {}};
  for (std::size_t i = 0; i < count; ++i) {
    series.time.push_back(0.01 * static_cast<double>(i));
    series.value.push_back(i == spike_at ? 5.0 : std::sin(0.001 * static_cast<double>(i)));
  }
  return series;
}

TEST(SeriesDecimation, ASeriesThatFitsIsKeptWhole) {
  const Series series = ramp_with_spike(100, 50);
  const Series cut = decimate_series(series, 100);
  EXPECT_EQ(cut.time, series.time);
  EXPECT_EQ(cut.value, series.value);
}

// 100000 samples to at most 1000, in time order, with the one-sample spike and the extremes kept.
TEST(SeriesDecimation, KeepsPeaksAndOrder) {
  const Series series = ramp_with_spike(100000, 61234);
  const Series cut = decimate_series(series, 1000);
  EXPECT_EQ(cut.name, "heading_offset");
  EXPECT_EQ(cut.unit, "rad");
  ASSERT_LE(cut.value.size(), 1000U);
  EXPECT_GE(cut.value.size(), 900U);
  ASSERT_EQ(cut.time.size(), cut.value.size());
  EXPECT_TRUE(std::is_sorted(cut.time.begin(), cut.time.end()));
  EXPECT_EQ(*std::max_element(cut.value.begin(), cut.value.end()), 5.0);
  EXPECT_DOUBLE_EQ(*std::min_element(cut.value.begin(), cut.value.end()),
                   *std::min_element(series.value.begin(), series.value.end()));
  // Every kept sample is a sample of the series, at its own time.
  for (std::size_t i = 0; i < cut.time.size(); ++i) {
    const auto index = static_cast<std::size_t>(std::lround(cut.time[i] / 0.01));
    EXPECT_EQ(cut.value[i], series.value[index]);
  }
}

// A stretch without finite values stays a gap (one non-finite sample per bucket), not a line.
TEST(SeriesDecimation, GapsStayGaps) {
  Series series = ramp_with_spike(10000, 0);
  for (std::size_t i = 4000; i < 6000; ++i) {
    series.value[i] = std::numeric_limits<double>::quiet_NaN();
  }
  const Series cut = decimate_series(series, 100);
  const auto gaps = std::count_if(cut.value.begin(), cut.value.end(),
                                  [](double value) { return std::isnan(value); });
  EXPECT_GE(gaps, 8);
  EXPECT_LE(cut.value.size(), 100U);
}

TEST(SeriesDecimation, IndexedSeriesAndBadLimits) {
  Series indexed{"flags", "", {}, std::vector<double>(5000, 1.0)};
  const Series cut = decimate_series(indexed, 50);
  EXPECT_TRUE(cut.time.empty());
  EXPECT_LE(cut.value.size(), 50U);
  EXPECT_THROW(decimate_series(indexed, 1), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::report
