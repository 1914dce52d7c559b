#include "x2car/report/series_decimation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace x2car::report {

Series decimate_series(const Series& series, std::size_t max_points) {
  if (max_points < 2) throw std::invalid_argument("decimate_series: max_points must be >= 2");
  const std::size_t count = series.value.size();
  if (count <= max_points) return series;
  const bool timed = !series.time.empty();
  Series cut{series.name, series.unit, {}, {}};
  const std::size_t buckets = max_points / 2;
  cut.value.reserve(2 * buckets);
  if (timed) cut.time.reserve(2 * buckets);
  const auto keep = [&](std::size_t index) {
    cut.value.push_back(series.value[index]);
    if (timed) cut.time.push_back(series.time[index]);
  };
  for (std::size_t bucket = 0; bucket < buckets; ++bucket) {
    const std::size_t first = bucket * count / buckets;
    const std::size_t end = (bucket + 1) * count / buckets;
    std::size_t lowest = end;
    std::size_t highest = end;
    for (std::size_t i = first; i < end; ++i) {
      const double value = series.value[i];
      if (!std::isfinite(value)) continue;
      if (lowest == end || value < series.value[lowest]) lowest = i;
      if (highest == end || value > series.value[highest]) highest = i;
    }
    if (lowest == end) {
      keep(first);
      continue;
    }
    keep(std::min(lowest, highest));
    if (lowest != highest) keep(std::max(lowest, highest));
  }
  return cut;
}

Series thin_series(const Series& series, std::size_t max_points) {
  if (max_points < 1) throw std::invalid_argument("thin_series: max_points must be >= 1");
  const std::size_t count = series.value.size();
  if (count <= max_points) return series;
  const std::size_t stride = (count + max_points - 1) / max_points;
  const bool timed = !series.time.empty();
  Series cut{series.name, series.unit, {}, {}};
  for (std::size_t i = 0; i < count; i += stride) {
    cut.value.push_back(series.value[i]);
    if (timed) cut.time.push_back(series.time[i]);
  }
  return cut;
}

}  // namespace x2car::report
