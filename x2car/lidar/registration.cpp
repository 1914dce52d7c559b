#include "x2car/lidar/registration.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/lidar/se3.hpp"

namespace x2car::lidar {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Sums of the Gauss-Newton normal equations of point-to-point ICP with the pose perturbed on the
// left: q = T p, residual r = q - m, Jacobian J = [I, -[q]x], so that
//   J^T J = [[I, -[q]x], [[q]x, |q|^2 I - q q^T]],   J^T r = [r; q x r].
// Keeping only the weighted sums below (instead of a 6x6 per point) makes a point cost ~30 flops.
struct NormalEquationSums {
  double weight = 0.0;                                     // sum w
  Eigen::Vector3d weighted_q = Eigen::Vector3d::Zero();    // sum w q
  Eigen::Matrix3d weighted_qq = Eigen::Matrix3d::Zero();   // sum w q q^T
  Eigen::Vector3d weighted_r = Eigen::Vector3d::Zero();    // sum w r
  Eigen::Vector3d weighted_qxr = Eigen::Vector3d::Zero();  // sum w q x r
  // Point-to-plane terms, e = n^T r with J = [n^T, (q x n)^T], accumulated as they come.
  Matrix6d plane_h = Matrix6d::Zero();  // sum w J^T J
  Vector6d plane_g = Vector6d::Zero();  // sum w J^T e
  // Sum of squared residuals (|r|^2, or e^2 on planes), unweighted, for the rms.
  double squared_residuals = 0.0;
  std::size_t count = 0;

  NormalEquationSums& operator+=(const NormalEquationSums& other) {
    weight += other.weight;
    weighted_q += other.weighted_q;
    weighted_qq += other.weighted_qq;
    weighted_r += other.weighted_r;
    weighted_qxr += other.weighted_qxr;
    plane_h += other.plane_h;
    plane_g += other.plane_g;
    squared_residuals += other.squared_residuals;
    count += other.count;
    return *this;
  }
};

// Geman-McClure weight: rho(r) = (kappa^2 r^2 / 2) / (kappa^2 + r^2) gives the IRLS weight
// rho'(r) / r = (kappa^2 / (kappa^2 + r^2))^2 (KISS-ICP Eq. 10-11).
double geman_mcclure_weight(double residual2, double kappa2) {
  const double ratio = kappa2 / (kappa2 + residual2);
  return ratio * ratio;
}

// Data association and accumulation for one range of source points (KISS-ICP Eq. 9).
NormalEquationSums associate_and_accumulate(
    std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> source_normals,
    const VoxelHashMap& map, std::span<VoxelHashMap::Neighbourhood> neighbourhoods,
    const Eigen::Matrix3f& rotation, const Eigen::Vector3f& translation, float max_distance2,
    double kappa2, double point_to_point_weight, const tbb::blocked_range<std::size_t>& range,
    NormalEquationSums sums) {
  for (std::size_t i = range.begin(); i != range.end(); ++i) {
    const Eigen::Vector3f q = rotation * source[i] + translation;
    Eigen::Vector3f m;
    float distance2 = 0.0f;
    if (!map.closest_point(q, m, distance2, neighbourhoods[i]) || distance2 > max_distance2) {
      continue;
    }
    const Eigen::Vector3d qd = q.cast<double>();
    const Eigen::Vector3d r = (q - m).cast<double>();
    if (!source_normals.empty() && source_normals[i] != Eigen::Vector3f::Zero()) {
      const Eigen::Vector3d n = (rotation * source_normals[i]).template cast<double>();
      const double e = n.dot(r);
      const double w = geman_mcclure_weight(e * e, kappa2);
      Vector6d j;
      j << n, qd.cross(n);
      sums.plane_h.noalias() += (w * j) * j.transpose();
      sums.plane_g += (w * e) * j;
      sums.squared_residuals += e * e;
      ++sums.count;
      continue;
    }
    const double w = point_to_point_weight * geman_mcclure_weight(distance2, kappa2);
    sums.weight += w;
    sums.weighted_q += w * qd;
    sums.weighted_qq += w * qd * qd.transpose();
    sums.weighted_r += w * r;
    sums.weighted_qxr += w * qd.cross(r);
    sums.squared_residuals += distance2;
    ++sums.count;
  }
  return sums;
}

// The 6x6 system H x = -g from the sums (see NormalEquationSums).
void build_linear_system(const NormalEquationSums& s, Matrix6d& h, Vector6d& g) {
  const Eigen::Matrix3d q_hat = hat(s.weighted_q);
  h.topLeftCorner<3, 3>() = s.weight * Eigen::Matrix3d::Identity();
  h.topRightCorner<3, 3>() = -q_hat;
  h.bottomLeftCorner<3, 3>() = q_hat;
  h.bottomRightCorner<3, 3>() = s.weighted_qq.trace() * Eigen::Matrix3d::Identity() - s.weighted_qq;
  g << s.weighted_r, s.weighted_qxr;
  h += s.plane_h;
  g += s.plane_g;
}

}  // namespace

void IcpSettings::Check() const {
  const OptionsCheck check("IcpSettings");
  check.positive("max_correspondence_distance", max_correspondence_distance);
  check.positive("kernel_scale", kernel_scale);
  check.non_negative("point_to_point_weight", point_to_point_weight);
  check.at_least("max_iterations", max_iterations, 1);
  check.positive("convergence", convergence);
}

IcpResult align_to_map(std::span<const Eigen::Vector3f> source,
                       std::span<const Eigen::Vector3f> source_normals, const VoxelHashMap& map,
                       const Eigen::Isometry3d& initial_guess, const IcpSettings& settings,
                       std::span<VoxelHashMap::Neighbourhood> neighbourhoods) {
  settings.Check();
  if (neighbourhoods.size() != source.size()) {
    throw std::invalid_argument("align_to_map: one neighbourhood per source point");
  }
  IcpResult result;
  result.world_from_source = initial_guess;
  const float max_distance2 = static_cast<float>(settings.max_correspondence_distance *
                                                 settings.max_correspondence_distance);
  const double kappa2 = settings.kernel_scale * settings.kernel_scale;
  // Deterministic: the same chunks summed in the same order whatever the threads do, so that a
  // log gives the same poses on every run.
  const tbb::blocked_range<std::size_t> all(0, source.size(), 256);
  Vector6d previous_update = Vector6d::Zero();
  for (int iteration = 1; iteration <= settings.max_iterations; ++iteration) {
    const Eigen::Matrix3f rotation = result.world_from_source.linear().cast<float>();
    const Eigen::Vector3f translation = result.world_from_source.translation().cast<float>();
    const NormalEquationSums sums = tbb::parallel_deterministic_reduce(
        all, NormalEquationSums{},
        [&](const tbb::blocked_range<std::size_t>& range, NormalEquationSums partial) {
          return associate_and_accumulate(source, source_normals, map, neighbourhoods, rotation,
                                          translation, max_distance2, kappa2,
                                          settings.point_to_point_weight, range, partial);
        },
        [](NormalEquationSums a, const NormalEquationSums& b) { return a += b; });
    result.iterations = iteration;
    result.correspondences = sums.count;
    result.rms_residual =
        sums.count > 0 ? std::sqrt(sums.squared_residuals / static_cast<double>(sums.count)) : 0.0;
    result.last_update = std::numeric_limits<double>::infinity();
    if (sums.count < 6) break;
    Matrix6d h;
    Vector6d g;
    build_linear_system(sums, h, g);
    const Eigen::LDLT<Matrix6d> ldlt(h);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) break;
    const Vector6d update = -ldlt.solve(g);
    if (!update.allFinite()) break;
    result.world_from_source = se3_exp(update) * result.world_from_source;
    result.last_update = update.norm();
    // Converged, or stepping back and forth between two sets of nearest neighbours.
    if (update.norm() < settings.convergence ||
        (update + previous_update).norm() < settings.convergence) {
      result.converged = true;
      break;
    }
    previous_update = update;
  }
  return result;
}

ConstraintStrength constraint_strength(std::span<const Eigen::Vector3f> source,
                                       const VoxelHashMap& map,
                                       const Eigen::Isometry3d& world_from_source,
                                       std::size_t max_samples) {
  // A voxel is planar (or linear) when its smallest (middle) spread is below this share of the
  // next one.
  constexpr float kFlatness = 0.1f;
  constexpr std::size_t kMinVoxelPoints = 3;  // the second sweep sees a map of one sweep
  ConstraintStrength strength;
  if (source.empty() || max_samples == 0) return strength;
  const std::size_t stride = std::max<std::size_t>(1, source.size() / max_samples);
  const Eigen::Matrix3f rotation = world_from_source.linear().cast<float>();
  const Eigen::Vector3f translation = world_from_source.translation().cast<float>();
  Eigen::Matrix3d translation_information = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rotation_information = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < source.size(); i += stride) {
    const Eigen::Vector3f direction = rotation * source[i];
    // The voxel of the point's nearest map point: a surface on a voxel boundary may put the
    // point itself into the empty voxel beside it.
    Eigen::Vector3f closest;
    float distance2 = 0.0f;
    if (!map.closest_point(direction + translation, closest, distance2)) continue;
    const std::span<const Eigen::Vector3f> voxel = map.voxel_points(closest);
    if (voxel.size() < kMinVoxelPoints) continue;
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    for (const Eigen::Vector3f& p : voxel) mean += p;
    mean /= static_cast<float>(voxel.size());
    Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();
    for (const Eigen::Vector3f& p : voxel) covariance += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eigen;
    eigen.computeDirect(covariance);
    const Eigen::Vector3f spread = eigen.eigenvalues().cwiseMax(0.0f);  // increasing
    const Eigen::Vector3d u = direction.normalized().cast<double>();
    Eigen::Matrix3d information;
    if (spread(0) < kFlatness * spread(1)) {
      const Eigen::Vector3d n = eigen.eigenvectors().col(0).cast<double>();
      translation_information += n * n.transpose();
      const Eigen::Vector3d torque = u.cross(n);
      rotation_information += torque * torque.transpose();
    } else if (spread(1) < kFlatness * spread(2)) {
      const Eigen::Vector3d d = eigen.eigenvectors().col(2).cast<double>();
      translation_information += 0.5 * (Eigen::Matrix3d::Identity() - d * d.transpose());
      const Eigen::Matrix3d u_hat = hat(u);
      rotation_information +=
          0.5 * u_hat * (Eigen::Matrix3d::Identity() - d * d.transpose()) * u_hat.transpose();
    } else {
      continue;
    }
    ++strength.shaped_voxels;
  }
  if (strength.shaped_voxels == 0) return strength;
  const double n = static_cast<double>(strength.shaped_voxels);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen_translation(translation_information / n,
                                                                   Eigen::EigenvaluesOnly);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen_rotation(rotation_information / n,
                                                                Eigen::EigenvaluesOnly);
  strength.translation = std::max(0.0, eigen_translation.eigenvalues()(0));
  strength.rotation = std::max(0.0, eigen_rotation.eigenvalues()(0));
  return strength;
}

}  // namespace x2car::lidar
