#include "x2car/eval/segments.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "x2car/core/options_check.hpp"

namespace x2car::eval {

void SegmentOptions::Check() const {
  const OptionsCheck check("SegmentOptions");
  check.positive("segment_s", segment_s);
  check.in_range("min_last_share", min_last_share, 0.0, 1.0);
  check.in_range("max_straight_heading_range", max_straight_heading_range, 0.0, kPi,
                 Bounds::kOpenMin);
}

std::vector<TimeSpan> cut_into_segments(double start_s, double end_s,
                                        const SegmentOptions& options) {
  options.Check();
  std::vector<TimeSpan> spans;
  if (!(end_s > start_s)) return spans;
  for (double begin = start_s; begin < end_s; begin += options.segment_s) {
    const double end = std::min(begin + options.segment_s, end_s);
    const bool whole = end - begin >= options.segment_s - 1e-9;
    if (whole || end - begin >= options.min_last_share * options.segment_s) {
      spans.push_back({begin, end});
    }
    if (!whole) break;
  }
  return spans;
}

bool is_straight(std::span<const io::InsRecord> records, const TimeSpan& span,
                 const SegmentOptions& options) {
  std::optional<double> previous;
  double unwrapped = 0.0;
  double low = 0.0;
  double high = 0.0;
  for (const io::InsRecord& record : records) {
    if (!span.contains(record.time)) continue;
    if (previous) unwrapped += wrap_angle(record.attitude.yaw - *previous);
    previous = record.attitude.yaw;
    low = std::min(low, unwrapped);
    high = std::max(high, unwrapped);
  }
  return previous.has_value() && high - low <= options.max_straight_heading_range;
}

std::vector<SegmentResult> calibrate_segments(
    const std::vector<TimeSpan>& spans,
    const std::function<CalibrationResult(const TimeSpan&)>& calibrate_segment,
    std::span<const io::InsRecord> ins, bool parallel, const SegmentOptions& options,
    const std::function<void(std::size_t done, std::size_t total)>& progress) {
  options.Check();
  std::vector<SegmentResult> results(spans.size());
  std::mutex progress_mutex;
  std::size_t done = 0;
  const auto run = [&](std::size_t i) {
    results[i].span = spans[i];
    results[i].straight = !ins.empty() && is_straight(ins, spans[i], options);
    results[i].result = calibrate_segment(spans[i]);
    if (progress) {
      const std::lock_guard lock(progress_mutex);
      progress(++done, spans.size());
    }
  };
  if (parallel) {
    tbb::parallel_for(std::size_t{0}, spans.size(), run);
  } else {
    for (std::size_t i = 0; i < spans.size(); ++i) run(i);
  }
  return results;
}

namespace {

std::optional<double> sample_std(const std::vector<double>& values) {
  if (values.size() < 2) return std::nullopt;
  double mean = 0.0;
  for (double value : values) mean += value;
  mean /= static_cast<double>(values.size());
  double sum = 0.0;
  for (double value : values) sum += (value - mean) * (value - mean);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

// `angle`: unwrapped around the first segment's value, so that a radar facing backwards (yaws
// near +-pi) has a mean and a spread.
AngleSpread spread_of(std::span<const SegmentResult> segments,
                      std::optional<double> CalibrationResult::*value, bool angle) {
  std::vector<double> all;
  std::vector<double> straight;
  for (const SegmentResult& segment : segments) {
    if (!segment.result.ok() || !(segment.result.*value)) continue;
    double v = *(segment.result.*value);
    if (angle && !all.empty()) v = all.front() + wrap_angle(v - all.front());
    all.push_back(v);
    if (segment.straight) straight.push_back(v);
  }
  AngleSpread spread;
  spread.count = static_cast<int>(all.size());
  spread.straight_count = static_cast<int>(straight.size());
  if (!all.empty()) {
    double sum = 0.0;
    for (double v : all) sum += v;
    spread.mean = sum / static_cast<double>(all.size());
    if (angle) spread.mean = wrap_angle(*spread.mean);
  }
  spread.std_all = sample_std(all);
  spread.std_straight = sample_std(straight);
  return spread;
}

}  // namespace

SegmentSummary summarise_segments(std::span<const SegmentResult> segments) {
  SegmentSummary summary;
  summary.segments = static_cast<int>(segments.size());
  double seconds = 0.0;
  for (const SegmentResult& segment : segments) {
    if (segment.result.ok()) ++summary.with_estimate;
    seconds += segment.result.seconds;
  }
  if (!segments.empty()) summary.mean_seconds = seconds / static_cast<double>(segments.size());
  summary.roll = spread_of(segments, &CalibrationResult::roll, true);
  summary.pitch = spread_of(segments, &CalibrationResult::pitch, true);
  summary.yaw = spread_of(segments, &CalibrationResult::yaw, true);
  summary.z = spread_of(segments, &CalibrationResult::z, false);
  return summary;
}

}  // namespace x2car::eval
