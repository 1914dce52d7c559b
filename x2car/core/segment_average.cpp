#include "x2car/core/segment_average.hpp"

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

// Means of the inlier samples over consecutive blocks of block_s seconds, as deviations from
// `reference`, weighted by each block's duration: the units the bootstrap resamples.
void block_means(std::span<const double> times, std::span<const double> angles,
                 const Segmentation& segmentation, const std::vector<std::uint8_t>& inliers,
                 double reference, double block_s, std::vector<double>& values,
                 std::vector<double>& weights) {
  for (const TimeSegment& segment : segmentation.segments) {
    std::size_t i = segment.begin;
    while (i < segment.end) {
      const double block_start = times[i];
      double sum = 0.0;
      std::int64_t count = 0;
      std::size_t j = i;
      for (; j < segment.end && times[j] < block_start + block_s; ++j) {
        if (inliers[j] == 0) continue;
        sum += angle_difference(angles[j], reference);
        ++count;
      }
      if (count > 0) {
        values.push_back(sum / static_cast<double>(count));
        weights.push_back(std::max(times[j - 1] - block_start, 1e-9));
      }
      i = j;
    }
  }
}

// Standard error of the mean of the inlier samples when there are not even two blocks: treats the
// samples as independent, which is optimistic, but there is nothing better to go on.
double sample_standard_error(std::span<const double> angles,
                             const std::vector<std::uint8_t>& inliers, double reference) {
  std::vector<double> deviations;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (inliers[i] != 0) deviations.push_back(angle_difference(angles[i], reference));
  }
  if (deviations.size() < 2) return 0.0;
  return standard_deviation(deviations) / std::sqrt(static_cast<double>(deviations.size()));
}

}  // namespace

void SegmentAverageOptions::Check() const {
  outliers.Check();
  bootstrap.Check();
  const OptionsCheck check("SegmentAverageOptions");
  check.at_least("min_segments_for_spread", min_segments_for_spread, 2);
  check.positive("block_s", block_s);
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

  if (static_cast<int>(average.segments.size()) >= options.min_segments_for_spread) {
    average.standard_error = standard_error_of_weighted_mean(deviations.values, segment_weights);
    return average;
  }
  std::vector<double> block_values;
  std::vector<double> block_weights;
  block_means(times, angles, segmentation, average.inliers, average.value, options.block_s,
              block_values, block_weights);
  if (block_values.size() < 2) {
    average.standard_error = sample_standard_error(angles, average.inliers, average.value);
    return average;
  }
  average.standard_error_from_bootstrap = true;
  average.standard_error = bootstrap_standard_error(
      block_values, block_weights,
      [](std::span<const double> values, std::span<const double> weights) {
        return weighted_mean(values, weights);
      },
      options.bootstrap);
  return average;
}

}  // namespace x2car
