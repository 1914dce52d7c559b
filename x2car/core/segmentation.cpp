#include "x2car/core/segmentation.hpp"

#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"

namespace x2car {
namespace {

enum class SampleState { kValid, kExcluded, kSlow, kCurved };

SampleState classify(double speed, double curvature, const SegmentationOptions& options) {
  if (!(std::isfinite(speed) && speed >= options.min_speed)) return SampleState::kSlow;
  if (!(std::isfinite(curvature) && std::abs(curvature) <= options.max_abs_curvature &&
        speed * speed * std::abs(curvature) <= options.max_abs_lateral_acceleration)) {
    return SampleState::kCurved;
  }
  return SampleState::kValid;
}

// Shrinks [begin, end) by end_trim_s at both ends and keeps it when it is still long enough.
void keep_trimmed_run(std::span<const double> times, std::size_t begin, std::size_t end,
                      const SegmentationOptions& options, Segmentation& segmentation) {
  const std::size_t run_size = end - begin;
  std::size_t first = begin;
  std::size_t last = end;  // exclusive
  while (first < last && times[first] < times[begin] + options.end_trim_s) ++first;
  while (last > first && times[last - 1] > times[end - 1] - options.end_trim_s) --last;
  const std::size_t kept = last - first;
  segmentation.rejections.trimmed += static_cast<std::int64_t>(run_size - kept);
  if (kept == 0 || times[last - 1] - times[first] < options.min_duration_s) {
    segmentation.rejections.short_run += static_cast<std::int64_t>(kept);
    return;
  }
  segmentation.segments.push_back({first, last, times[first], times[last - 1]});
}

}  // namespace

void SegmentationOptions::Check() const {
  const OptionsCheck check("SegmentationOptions");
  check.non_negative("min_speed", min_speed);
  check.positive("max_abs_curvature", max_abs_curvature);
  check.that(max_abs_lateral_acceleration > 0.0, "max_abs_lateral_acceleration",
             "must be > 0 (infinite: no limit)", max_abs_lateral_acceleration);
  check.non_negative("min_duration_s", min_duration_s);
  check.positive("max_gap_s", max_gap_s);
  check.non_negative("end_trim_s", end_trim_s);
}

std::size_t Segmentation::sample_count() const {
  std::size_t count = 0;
  for (const auto& segment : segments) count += segment.size();
  return count;
}

Segmentation segment_runs(std::span<const double> times, std::span<const double> speeds,
                          std::span<const double> curvatures, const SegmentationOptions& options,
                          std::span<const std::uint8_t> excluded) {
  options.Check();
  if (speeds.size() != times.size() || curvatures.size() != times.size()) {
    throw std::invalid_argument("segmentation: times, speeds and curvatures differ in size");
  }
  if (!excluded.empty() && excluded.size() != times.size()) {
    throw std::invalid_argument("segmentation: the exclusion mask and the times differ in size");
  }
  Segmentation segmentation;
  std::size_t run_begin = 0;
  bool in_run = false;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const SampleState state = !excluded.empty() && excluded[i] != 0
                                  ? SampleState::kExcluded
                                  : classify(speeds[i], curvatures[i], options);
    const bool gap_before = in_run && times[i] - times[i - 1] > options.max_gap_s;
    if (in_run && (state != SampleState::kValid || gap_before)) {
      keep_trimmed_run(times, run_begin, i, options, segmentation);
      in_run = false;
    }
    if (state == SampleState::kExcluded) ++segmentation.rejections.excluded;
    if (state == SampleState::kSlow) ++segmentation.rejections.slow;
    if (state == SampleState::kCurved) ++segmentation.rejections.curved;
    if (state == SampleState::kValid && !in_run) {
      run_begin = i;
      in_run = true;
    }
  }
  if (in_run) keep_trimmed_run(times, run_begin, times.size(), options, segmentation);
  return segmentation;
}

}  // namespace x2car
