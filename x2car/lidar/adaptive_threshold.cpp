#include "x2car/lidar/adaptive_threshold.hpp"

#include <cmath>

namespace x2car::lidar {
namespace {

// The largest displacement `pose` causes on a point within `max_range` of the sensor (Eq. 7).
double displacement_bound(const Eigen::Isometry3d& pose, double max_range) {
  const double angle = Eigen::AngleAxisd(pose.linear()).angle();
  return pose.translation().norm() + 2.0 * max_range * std::sin(0.5 * angle);
}

}  // namespace

AdaptiveThreshold::AdaptiveThreshold(double initial_sigma, double max_range, double min_correction)
    : initial_sigma_(initial_sigma), max_range_(max_range), min_correction_(min_correction) {}

void AdaptiveThreshold::update(const Eigen::Isometry3d& correction) {
  const double error = displacement_bound(correction, max_range_);
  if (error <= min_correction_) return;
  sum_squared_ += error * error;
  ++samples_;
}

double AdaptiveThreshold::sigma() const {
  return samples_ == 0 ? initial_sigma_ : std::sqrt(sum_squared_ / static_cast<double>(samples_));
}

}  // namespace x2car::lidar
