// Timestamped SE(3) poses and their interpolation.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <span>
#include <vector>

namespace x2car {

struct StampedPose {
  double time = 0.0;  // [s]
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
};

// Pose between two poses: linear in position, slerp in rotation; `fraction` in [0, 1].
Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double fraction);

// A time-ordered sequence of poses. Construction checks that times are finite and strictly
// increasing (std::invalid_argument otherwise), so lookups can bisect.
class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(std::vector<StampedPose> poses);

  const std::vector<StampedPose>& poses() const { return poses_; }
  std::size_t size() const { return poses_.size(); }
  bool empty() const { return poses_.empty(); }
  double start_time() const { return poses_.front().time; }
  double end_time() const { return poses_.back().time; }

  // Pose at `time` [s]; nullopt outside [start_time, end_time] (never extrapolates).
  std::optional<Eigen::Isometry3d> pose_at(double time) const;

  // Poses at many times; entries outside the span are nullopt. `times` need not be sorted.
  std::vector<std::optional<Eigen::Isometry3d>> poses_at(std::span<const double> times) const;

  // Planar (x, y) positions and times, the input of the planar-track smoother.
  std::vector<double> times() const;
  std::vector<double> positions_x() const;
  std::vector<double> positions_y() const;

 private:
  std::vector<StampedPose> poses_;
};

}  // namespace x2car
