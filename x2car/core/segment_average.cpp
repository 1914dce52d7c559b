#include "x2car/core/segment_average.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"

namespace x2car {
namespace {

// Wrapped deviations of angles[begin, end) from their circular mean, and that mean.
struct Deviations {
  double reference = 0.0;  // [rad]
  std::vector<double> values;
};

Deviations deviations_from_circular_mean(std::span<const double> angles) {
  Deviations deviations;
  deviations.reference = circular_mean(angles);
  deviations.values.reserve(angles.size());
  for (const double angle : angles) {
    deviations.values.push_back(angle_difference(angle, deviations.reference));
  }
  return deviations;
}

// Median/MAD rejection inside one segment, then the mean of what is left.
SegmentEstimate estimate_segment(std::span<const double> times, std::span<const double> angles,
                                 const TimeSegment& segment, const SegmentAverageOptions& options,
                                 std::vector<std::uint8_t>& inliers) {
  const std::span<const double> segment_angles = angles.subspan(segment.begin, segment.size());
  for (const double angle : segment_angles) {
    if (!std::isfinite(angle)) {
      throw std::invalid_argument("average_over_segments: an angle inside a segment is not finite");
    }
  }
  const Deviations deviations = deviations_from_circular_mean(segment_angles);
  const std::vector<bool> mask = mad_inlier_mask(deviations.values, options.outliers);
  SegmentEstimate estimate;
  estimate.start_time = times[segment.begin];
  estimate.end_time = times[segment.end - 1];
  estimate.weight = segment.duration();
  double sum = 0.0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) {
      ++estimate.outliers;
      continue;
    }
    inliers[segment.begin + i] = 1;
    sum += deviations.values[i];
    ++estimate.samples;
  }
  // The median is always an inlier, so samples > 0.
  estimate.value = wrap_angle(deviations.reference + sum / static_cast<double>(estimate.samples));
  return estimate;
}

// The three data-driven standard errors of the average (core/standard_error.hpp), from the inlier
// samples' wrapped deviations from it and the segment estimates'.
void set_standard_errors(std::span<const double> times, std::span<const double> angles,
                         const std::vector<double>& segment_deviations,
                         const std::vector<double>& segment_weights,
                         const SegmentAverageOptions& options, SegmentAverage& average) {
  std::vector<double> inlier_times;
  std::vector<double> deviations;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (average.inliers[i] == 0) continue;
    inlier_times.push_back(times[i]);
    deviations.push_back(angle_difference(angles[i], average.value));
  }
  if (deviations.size() >= 2) {
    const SeriesStandardError series =
        series_standard_error(inlier_times, deviations, options.blocks);
    average.formal_standard_error = series.formal;
    average.block_standard_error = series.block;
  }
  const auto segments = static_cast<int>(segment_deviations.size());
  if (segments >= options.min_segments_for_spread) {
    average.spread_standard_error =
        small_sample_factor(segments - 1) *
        standard_error_of_weighted_mean(segment_deviations, segment_weights);
  }
  const std::array<double, 3> parts{average.block_standard_error, average.spread_standard_error,
                                    average.formal_standard_error};
  average.standard_error = combined_standard_error(parts);
}

}  // namespace

void SegmentAverageOptions::Check() const {
  outliers.Check();
  const OptionsCheck check("SegmentAverageOptions");
  blocks.Check();
  check.at_least("min_segments_for_spread", min_segments_for_spread, 2);
}

SegmentAverage average_over_segments(std::span<const double> times, std::span<const double> angles,
                                     const Segmentation& segmentation,
                                     const SegmentAverageOptions& options) {
  options.Check();
  if (angles.size() != times.size()) {
    throw std::invalid_argument("average_over_segments: times and angles differ in size");
  }
  if (segmentation.segments.empty()) {
    throw std::invalid_argument("average_over_segments: no segment to average");
  }
  SegmentAverage average;
  average.inliers.assign(angles.size(), 0);
  std::vector<double> segment_values;
  std::vector<double> segment_weights;
  for (const TimeSegment& segment : segmentation.segments) {
    if (segment.begin >= segment.end || segment.end > times.size()) {
      throw std::invalid_argument("average_over_segments: a segment lies outside the samples");
    }
    const SegmentEstimate estimate =
        estimate_segment(times, angles, segment, options, average.inliers);
    average.outliers += estimate.outliers;
    average.segments.push_back(estimate);
    segment_values.push_back(estimate.value);
    // A zero-length segment (one sample) still counts, a little.
    segment_weights.push_back(std::max(estimate.weight, 1e-9));
  }
  const Deviations deviations = deviations_from_circular_mean(segment_values);
  const double mean_deviation = weighted_mean(deviations.values, segment_weights);
  average.value = wrap_angle(deviations.reference + mean_deviation);

  set_standard_errors(times, angles, deviations.values, segment_weights, options, average);
  return average;
}

}  // namespace x2car
