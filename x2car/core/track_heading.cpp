#include "x2car/core/track_heading.hpp"

#include <cmath>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car {

std::vector<double> sensor_headings(std::span<const Eigen::Matrix3d> world_from_sensor) {
  std::vector<double> headings(world_from_sensor.size());
  for (std::size_t i = 0; i < headings.size(); ++i) {
    headings[i] = euler_from_rotation(world_from_sensor[i]).yaw;
  }
  return headings;
}

std::vector<double> heading_offsets(std::span<const double> sensor_heading_enu,
                                    std::span<const double> track_heading_enu) {
  std::vector<double> offsets(sensor_heading_enu.size());
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    offsets[i] = angle_difference(sensor_heading_enu[i], track_heading_enu[i]);
  }
  return offsets;
}

std::vector<std::uint8_t> find_reversing(std::span<const double> offsets,
                                         std::span<const double> speeds, double min_speed) {
  std::vector<double> moving;
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    if (speeds[i] >= min_speed) moving.push_back(offsets[i]);
  }
  std::vector<std::uint8_t> reversing(offsets.size(), 0);
  if (moving.empty() || mean_resultant_length(moving) < 1e-6) return reversing;
  const double usual_offset = circular_mean(moving);
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    reversing[i] =
        speeds[i] >= min_speed && std::abs(angle_difference(offsets[i], usual_offset)) > kPi / 2.0;
  }
  return reversing;
}

std::vector<double> yaw_rate_curvature(std::span<const double> times,
                                       std::span<const double> headings,
                                       std::span<const double> speeds,
                                       const PSplineOptions& spline_options) {
  std::vector<double> unwrapped(headings.begin(), headings.end());
  for (std::size_t i = 1; i < unwrapped.size(); ++i) {
    unwrapped[i] = unwrapped[i - 1] + angle_difference(headings[i], headings[i - 1]);
  }
  const PSpline heading_of_time = fit_pspline(times, unwrapped, spline_options);
  std::vector<double> curvature(times.size(), 0.0);
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (speeds[i] > 0.0) curvature[i] = heading_of_time.derivative(times[i], 1) / speeds[i];
  }
  return curvature;
}

SegmentAverage track_heading_yaw(std::span<const double> times, std::span<const double> offsets,
                                 const Segmentation& segments,
                                 const SegmentAverageOptions& options) {
  return average_over_segments(times, offsets, segments, options);
}

}  // namespace x2car
