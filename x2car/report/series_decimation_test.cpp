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

// Two series of one length drawn against each other keep their pairs.
TEST(SeriesDecimation, ThinningKeepsPairs) {
  Series x{"odometry_x", "m", {}, {}};
  Series y{"odometry_y", "m", {}, {}};
  for (int i = 0; i < 10007; ++i) {
    x.time.push_back(0.1 * i);
    y.time.push_back(0.1 * i);
    x.value.push_back(i);
    y.value.push_back(2.0 * i);
  }
  const Series thin_x = thin_series(x, 1000);
  const Series thin_y = thin_series(y, 1000);
  ASSERT_EQ(thin_x.value.size(), thin_y.value.size());
  EXPECT_LE(thin_x.value.size(), 1000U);
  EXPECT_GE(thin_x.value.size(), 900U);
  for (std::size_t i = 0; i < thin_x.value.size(); ++i) {
    EXPECT_EQ(thin_y.value[i], 2.0 * thin_x.value[i]);
    EXPECT_EQ(thin_x.time[i], thin_y.time[i]);
  }
  EXPECT_EQ(thin_series(x, 20000).value.size(), x.value.size());
}

}  // namespace
}  // namespace x2car::report
