// The adaptive correspondence threshold of KISS-ICP (Vizzo et al. 2023, Sec. III-C): the
// registration's correction of the constant-velocity prediction says how wrong predictions
// typically are; sigma is the root mean square of those corrections, measured as the largest
// displacement they cause on a point at max_range (Eq. 7-8: |dt| + 2 r_max sin(dtheta / 2)).
// Correspondences are searched within 3 sigma and the robust kernel's scale follows sigma.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>

namespace x2car::lidar {

class AdaptiveThreshold {
 public:
  // initial_sigma [m]: used until a correction has been counted; max_range [m]: of the sweeps;
  // min_correction [m]: smaller corrections are not counted (as KISS-ICP's min_motion_th): they
  // are below what the map's point spacing resolves, and counting them, as on a smooth drive or
  // standing still, would shrink sigma until the correspondences of the next jolt are missed.
  AdaptiveThreshold(double initial_sigma, double max_range, double min_correction);

  // `correction` = prediction^-1 * estimate.
  void update(const Eigen::Isometry3d& correction);

  double sigma() const;  // [m]
  std::size_t samples() const { return samples_; }

 private:
  double initial_sigma_;
  double max_range_;
  double min_correction_;
  double sum_squared_ = 0.0;
  std::size_t samples_ = 0;
};

}  // namespace x2car::lidar
