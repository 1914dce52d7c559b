// Combining per-sample measurements of one angle over the valid segments of a drive (DESIGN §2):
// per segment, reject outliers by median/MAD and average the rest; average the segments weighted
// by their duration; take the standard error from the spread of the segment estimates, or from a
// bootstrap over blocks of a few seconds when there are too few segments for the spread to be
// trusted. Shared by the calibrators that compare headings or directions sample by sample.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/segmentation.hpp"

namespace x2car {

struct SegmentAverageOptions {
  // Within a segment a sample is an outlier when it is more than k robust sigmas from the
  // segment's median; the floor keeps a very quiet segment from rejecting ordinary noise.
  OutlierRejectionOptions outliers{.k = 3.0, .min_sigma = rad_from_deg(0.005)};
  // With fewer segments than this the standard error comes from the block bootstrap below.
  int min_segments_for_spread = 5;
  double block_s = 5.0;  // [s] block length of the bootstrap; longer than the noise's correlation
  // Resamples the blocks' wrapped deviations from the mean, so no circular handling is needed.
  BootstrapOptions bootstrap{.resamples = 500, .seed = 1};

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
  double value = 0.0;           // duration-weighted mean of the segments, in (-pi, pi] [rad]
  double standard_error = 0.0;  // [rad]
  bool standard_error_from_bootstrap = false;
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
