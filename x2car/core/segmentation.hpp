// Splitting a sampled track into continuous runs that meet speed, curvature and
// lateral-acceleration limits for a minimum duration: the moving stretches on which heading
// comparisons are valid (the paper's straight ones, or with turns of low lateral acceleration too).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace x2car {

struct SegmentationOptions {
  double min_speed = 3.0;           // [m/s] slower samples have an unreliable heading
  double max_abs_curvature = 0.01;  // [1/m] |kappa| above this is a turn (radius < 100 m)
  // [m/s^2] |speed^2 * kappa| (the lateral acceleration) above this is a turn too; infinite: off.
  double max_abs_lateral_acceleration = std::numeric_limits<double>::infinity();
  double min_duration_s = 5.0;  // [s] shorter runs are dropped
  double max_gap_s = 0.5;       // [s] a larger gap between samples breaks a run
  double end_trim_s = 0.0;      // [s] cut from both ends of each run, where turns begin/end

  void Check() const;
};

// Samples [begin, end) of one run.
struct TimeSegment {
  std::size_t begin = 0;
  std::size_t end = 0;
  double start_time = 0.0;  // [s] time of sample `begin`
  double end_time = 0.0;    // [s] time of sample `end - 1`

  double duration() const { return end_time - start_time; }
  std::size_t size() const { return end - begin; }
};

// Why samples were not used, counted once each in the first reason that applies.
struct SegmentationRejections {
  std::int64_t slow = 0;       // speed below min_speed, or not finite
  std::int64_t curved = 0;     // |curvature| or lateral acceleration above its limit, or not finite
  std::int64_t trimmed = 0;    // within end_trim_s of a run's end
  std::int64_t short_run = 0;  // in a run shorter than min_duration_s after trimming
  std::int64_t excluded = 0;   // marked by the caller (e.g. reversing), checked first
};

struct Segmentation {
  std::vector<TimeSegment> segments;
  SegmentationRejections rejections;

  std::size_t sample_count() const;  // samples inside the segments
};

// `times` strictly increasing [s]; `speeds` [m/s] and `curvatures` [1/m] per sample; `excluded`
// empty or one flag per sample (non-zero: the caller rejects the sample for its own reason, which
// breaks a run like any other rejection). Throws std::invalid_argument when the sizes differ or the
// options are invalid.
Segmentation segment_runs(std::span<const double> times, std::span<const double> speeds,
                          std::span<const double> curvatures,
                          const SegmentationOptions& options = {},
                          std::span<const std::uint8_t> excluded = {});

}  // namespace x2car
