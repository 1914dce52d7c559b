#include "x2car/lidar/planar_normals.hpp"

#include <Eigen/Eigenvalues>

#include "x2car/core/options_check.hpp"

namespace x2car::lidar {

void PlanarityOptions::Check() const {
  const OptionsCheck check("PlanarityOptions");
  // A covariance of fewer than 3 points cannot show a plane.
  check.at_least("min_points", static_cast<double>(min_points), 3);
  check.in_range("max_flatness", max_flatness, 0.0, 1.0);
  check.non_negative("min_extent_m", min_extent_m);
}

void planar_normals(std::span<const Eigen::Vector3f> fine,
                    std::span<const std::uint32_t> voxel_of_fine,
                    std::span<const Eigen::Vector3f> coarse, const PlanarityOptions& options,
                    std::vector<PatchMoments>& moments, std::vector<Eigen::Vector3f>& normals) {
  moments.assign(coarse.size(), PatchMoments{});
  // Offsets from the voxel's kept point are small, so float sums keep the covariance exact enough.
  for (std::size_t k = 0; k < fine.size(); ++k) {
    const std::uint32_t voxel = voxel_of_fine[k];
    const Eigen::Vector3f offset = fine[k] - coarse[voxel];
    PatchMoments& m = moments[voxel];
    m.sum += offset;
    m.outer_sum.noalias() += offset * offset.transpose();
    ++m.count;
  }
  normals.assign(coarse.size(), Eigen::Vector3f::Zero());
  const float min_variance = options.min_extent_m * options.min_extent_m;
  for (std::size_t i = 0; i < coarse.size(); ++i) {
    const PatchMoments& m = moments[i];
    if (m.count < options.min_points) continue;
    const float n = static_cast<float>(m.count);
    const Eigen::Vector3f mean = m.sum / n;
    const Eigen::Matrix3f covariance = m.outer_sum / n - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eigen;
    eigen.computeDirect(covariance);
    const Eigen::Vector3f spread = eigen.eigenvalues();  // increasing
    if (spread(1) >= min_variance && spread(0) <= options.max_flatness * spread(1)) {
      normals[i] = eigen.eigenvectors().col(0).normalized();
    }
  }
}

}  // namespace x2car::lidar
