#include "x2car/core/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace x2car {

Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double fraction) {
  const Eigen::Quaterniond rotation_a(a.linear());
  const Eigen::Quaterniond rotation_b(b.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation_a.slerp(fraction, rotation_b).toRotationMatrix();
  pose.translation() = (1.0 - fraction) * a.translation() + fraction * b.translation();
  return pose;
}

Trajectory::Trajectory(std::vector<StampedPose> poses) : poses_(std::move(poses)) {
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    if (!std::isfinite(poses_[i].time)) {
      throw std::invalid_argument("trajectory: pose " + std::to_string(i) + " has no finite time");
    }
    if (i > 0 && !(poses_[i].time > poses_[i - 1].time)) {
      throw std::invalid_argument("trajectory: times not strictly increasing at pose " +
                                  std::to_string(i));
    }
  }
}

std::optional<Eigen::Isometry3d> Trajectory::pose_at(double time) const {
  if (poses_.empty() || !(time >= start_time() && time <= end_time())) return std::nullopt;
  const auto after =
      std::lower_bound(poses_.begin(), poses_.end(), time,
                       [](const StampedPose& pose, double t) { return pose.time < t; });
  if (after->time == time) return after->world_from_body;
  const auto before = std::prev(after);
  const double fraction = (time - before->time) / (after->time - before->time);
  return interpolate_pose(before->world_from_body, after->world_from_body, fraction);
}

std::vector<std::optional<Eigen::Isometry3d>> Trajectory::poses_at(
    std::span<const double> times) const {
  std::vector<std::optional<Eigen::Isometry3d>> result;
  result.reserve(times.size());
  for (const double time : times) result.push_back(pose_at(time));
  return result;
}

std::vector<double> Trajectory::times() const {
  std::vector<double> result;
  result.reserve(poses_.size());
  for (const auto& pose : poses_) result.push_back(pose.time);
  return result;
}

std::vector<double> Trajectory::positions_x() const {
  std::vector<double> result;
  result.reserve(poses_.size());
  for (const auto& pose : poses_) result.push_back(pose.world_from_body.translation().x());
  return result;
}

std::vector<double> Trajectory::positions_y() const {
  std::vector<double> result;
  result.reserve(poses_.size());
  for (const auto& pose : poses_) result.push_back(pose.world_from_body.translation().y());
  return result;
}

}  // namespace x2car
