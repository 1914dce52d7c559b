// Combining per-sample measurements of one angle over the valid segments of a drive (DESIGN §2):
// per segment, reject outliers by median/MAD and average the rest; average the segments weighted
// by their duration; take the standard error from what the data show of their correlated errors:
// the moving-block estimate over time, the spread of the segment estimates (both Student-t
// corrected for their few degrees of freedom), never below the independent-sample one
// (core/standard_error.hpp). Shared by the calibrators that compare headings or directions sample
// by sample.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/segmentation.hpp"
#include "x2car/core/standard_error.hpp"

namespace x2car {

struct SegmentAverageOptions {
  // Within a segment a sample is an outlier when it is more than k robust sigmas from the
  // segment's median; the floor keeps a very quiet segment from rejecting ordinary noise.
  OutlierRejectionOptions outliers{.k = 3.0, .min_sigma = rad_from_deg(0.005)};
  // The spread of the segment estimates counts towards the standard error from this many segments
  // on (Student-t corrected for their number: with 3 segments x 2.2).
  int min_segments_for_spread = 3;
  // The moving-block estimate over the inlier samples (core/standard_error.hpp): blocks longer
  // than the correlation time of the errors (GNSS multipath and atmosphere drift over ~10 s; the
  // odometry's over a few seconds).
  MovingBlockOptions blocks{.block_s = 10.0};

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct SegmentEstimate {
  double start_time = 0.0;    // [s]
  double end_time = 0.0;      // [s]
  std::int64_t samples = 0;   // inliers averaged
  std::int64_t outliers = 0;  // rejected by the MAD test
  double value = 0.0;         // mean of the inliers, in (-pi, pi] [rad]
  double weight = 0.0;        // the segment's duration [s]
};

struct SegmentAverage {
  double value = 0.0;  // duration-weighted mean of the segments, in (-pi, pi] [rad]
  // [rad]: the largest of the three below (core/standard_error.hpp). Biases the data cannot show
  // (a device's heading bias) are not in it: the calibrators add their floors.
  double standard_error = 0.0;
  double block_standard_error = 0.0;   // moving blocks over time, Student-t corrected [rad]
  double spread_standard_error = 0.0;  // segment spread, Student-t corrected; 0 if too few [rad]
  double formal_standard_error = 0.0;  // the inliers as independent samples, s / sqrt(n) [rad]
  std::vector<SegmentEstimate> segments;
  std::int64_t outliers = 0;          // samples rejected in all segments together
  std::vector<std::uint8_t> inliers;  // one flag per input sample: 1 = averaged
};

// `angles` [rad] holds one value per sample of `times` [s] (the times segment_runs saw); samples
// outside the segments are ignored and may be NaN. Angles are averaged as angles (wrapped
// deviations from a circular mean), so values near +-pi are safe. Throws std::invalid_argument when
// there is no segment, a segment lies outside the samples, the sizes differ or an angle inside a
// segment is not finite.
SegmentAverage average_over_segments(std::span<const double> times, std::span<const double> angles,
                                     const Segmentation& segmentation,
                                     const SegmentAverageOptions& options = {});

}  // namespace x2car
