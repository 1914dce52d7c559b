#include "x2car/lidar/odometry_error.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::lidar {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Distance along the path from the first pose to each pose [m].
std::vector<double> path_distances(std::span<const Eigen::Isometry3d> poses) {
  std::vector<double> distances(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    distances[i] = distances[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return distances;
}

// The first pose index at least `length` beyond `first` along the path; size() when none.
std::size_t segment_end(const std::vector<double>& distances, std::size_t first, double length) {
  for (std::size_t j = first; j < distances.size(); ++j) {
    if (distances[j] > distances[first] + length) return j;
  }
  return distances.size();
}

}  // namespace

void DriftOptions::Check() const {
  const OptionsCheck check("DriftOptions");
  check.that(!lengths_m.empty(), "lengths_m", "must not be empty");
  for (const double length : lengths_m) check.positive("lengths_m", length);
  check.at_least("step", static_cast<double>(step), 1);
}

Drift relative_drift(std::span<const Eigen::Isometry3d> estimate,
                     std::span<const Eigen::Isometry3d> truth, const DriftOptions& options) {
  options.Check();
  if (estimate.size() != truth.size()) {
    throw std::invalid_argument("relative_drift: estimate and truth differ in size");
  }
  const std::vector<double> distances = path_distances(truth);
  Drift drift;
  drift.path_length_m = distances.empty() ? 0.0 : distances.back();
  double translation_sum = 0.0;
  double rotation_sum = 0.0;
  for (const double length : options.lengths_m) {
    DriftAtLength at_length;
    at_length.length_m = length;
    double translation = 0.0;
    double rotation = 0.0;
    for (std::size_t first = 0; first < truth.size(); first += options.step) {
      const std::size_t last = segment_end(distances, first, length);
      if (last == truth.size()) break;
      const Eigen::Isometry3d error = (truth[first].inverse() * truth[last]).inverse() *
                                      (estimate[first].inverse() * estimate[last]);
      translation += error.translation().norm() / length;
      rotation += Eigen::AngleAxisd(error.linear()).angle() / length;
      ++at_length.segments;
    }
    const double n = static_cast<double>(at_length.segments);
    at_length.translation_percent = at_length.segments > 0 ? 100.0 * translation / n : kNaN;
    at_length.rotation_deg_per_100m =
        at_length.segments > 0 ? 100.0 * deg_from_rad(rotation / n) : kNaN;
    translation_sum += translation;
    rotation_sum += rotation;
    drift.segments += at_length.segments;
    drift.per_length.push_back(at_length);
  }
  const double n = static_cast<double>(drift.segments);
  drift.translation_percent = drift.segments > 0 ? 100.0 * translation_sum / n : kNaN;
  drift.rotation_deg_per_100m = drift.segments > 0 ? 100.0 * deg_from_rad(rotation_sum / n) : kNaN;
  return drift;
}

}  // namespace x2car::lidar
