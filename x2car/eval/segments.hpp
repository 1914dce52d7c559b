// The paper's evaluation protocol (its Table III, §IV): cut a log into segments of a minute,
// calibrate each on its own, and report how the estimates spread over the segments, over all of
// them and over those driven straight, and the share of segments that gave an estimate (issue 16
// item 2). The spread measures what a minute of driving pins down; the whole log's estimate is
// compared with the truth separately.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::eval {

struct SegmentOptions {
  double segment_s = 60.0;  // the paper's minute
  // A last piece shorter than this share of segment_s is dropped (it would be a segment of
  // another kind): with 0.5, a 119.9 s log gives two minutes, a 100 s log one.
  double min_last_share = 0.5;
  // A segment is "straight" when the car's heading stays within this range over it [rad]: the
  // paper reports its spread over straight driving separately, as turns change what is observed.
  double max_straight_heading_range = rad_from_deg(10.0);

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct TimeSpan {
  double start_s = 0.0;
  double end_s = 0.0;  // exclusive
  bool contains(double time_s) const { return time_s >= start_s && time_s < end_s; }
};

// [start, end) cut into segments of segment_s from the start; the last piece kept when it is at
// least min_last_share of a segment long. Empty when the log is shorter than that.
std::vector<TimeSpan> cut_into_segments(double start_s, double end_s,
                                        const SegmentOptions& options = {});

// Whether the GNSS/INS heading stays within max_straight_heading_range over the span (unwrapped);
// false when no record falls in it.
bool is_straight(std::span<const io::InsRecord> records, const TimeSpan& span,
                 const SegmentOptions& options = {});

struct SegmentResult {
  TimeSpan span;
  bool straight = false;
  CalibrationResult result;
};

// Calibrates every segment: `calibrate_segment(span)` runs the sensor's calibrator on the data in
// it; segments run in parallel (oneTBB) when `parallel`, else in order (a calibrator that is
// parallel inside, the LiDAR's). `straight` comes from `ins` when given. `progress` (when set) is
// called after each segment with the segments done and the total, one call at a time.
std::vector<SegmentResult> calibrate_segments(
    const std::vector<TimeSpan>& spans,
    const std::function<CalibrationResult(const TimeSpan&)>& calibrate_segment,
    std::span<const io::InsRecord> ins, bool parallel, const SegmentOptions& options = {},
    const std::function<void(std::size_t done, std::size_t total)>& progress = {});

// One angle over the segments that gave it [rad].
struct AngleSpread {
  int count = 0;           // segments that estimated it
  int straight_count = 0;  // of them, driven straight
  std::optional<double> mean;
  std::optional<double> std_all;       // sample std over the segments (two or more)
  std::optional<double> std_straight;  // over the straight ones (two or more)
};

struct SegmentSummary {
  int segments = 0;
  int with_estimate = 0;      // status ok
  double mean_seconds = 0.0;  // the calibrator's time per segment
  AngleSpread roll, pitch, yaw;
  AngleSpread z;  // [m], the LiDAR's height
};

// Over the segments whose status is ok.
SegmentSummary summarise_segments(std::span<const SegmentResult> segments);

}  // namespace x2car::eval
