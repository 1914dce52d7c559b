#include "x2car/lidar/ground.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "x2car/core/options_check.hpp"

namespace x2car::lidar {
namespace {

// A plane n . p + d = 0 with |n| = 1 and d > 0: the LiDAR origin lies on the side n points to.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;  // d [m]
};

// ---- seeded draws whose values the C++ standard fixes (mt19937_64's output is specified; the
// standard distributions are not, so they are not used) ------------------------------------

std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t stream) {  // splitmix64 finaliser
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::size_t draw_index(std::mt19937_64& rng, std::size_t count) {
  return static_cast<std::size_t>(rng() % count);  // modulo bias < count / 2^64: negligible
}

double draw_uniform(std::mt19937_64& rng) {  // in (0, 1)
  return (static_cast<double>(rng() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

double draw_normal(std::mt19937_64& rng) {  // Box-Muller
  const double u1 = draw_uniform(rng), u2 = draw_uniform(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// ---- 1. range and height filter --------------------------------------------------------------

bool finite_point(const io::LidarPoint& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// Keeps the points that can be road near the car (GroundOptions); returns how many were NaN/inf.
std::size_t filter_points(const io::PointCloud& sweep, const GroundOptions& options,
                          std::vector<Eigen::Vector3f>& filtered) {
  const double min_r2 = options.min_range_m * options.min_range_m;
  const double max_r2 = options.max_range_m * options.max_range_m;
  const double max_lateral =
      options.max_lateral_m > 0.0 ? options.max_lateral_m : std::numeric_limits<double>::infinity();
  const double tan_tilt = std::tan(options.max_tilt);
  // The sideways distance is p . (-sin a, cos a), across the travel's direction (cos a, sin a).
  const double across_x = -std::sin(options.travel_yaw);
  const double across_y = std::cos(options.travel_yaw);
  std::size_t invalid = 0;
  filtered.clear();
  for (const io::LidarPoint& p : sweep.points) {
    if (!finite_point(p)) {
      ++invalid;
      continue;
    }
    const double r2 = double{p.x} * p.x + double{p.y} * p.y;
    if (r2 < min_r2 || r2 > max_r2 || std::abs(across_x * p.x + across_y * p.y) > max_lateral) {
      continue;
    }
    const double slack = std::sqrt(r2) * tan_tilt;
    if (p.z > -options.min_height_m + slack || p.z < -options.max_height_m - slack) continue;
    filtered.emplace_back(p.x, p.y, p.z);
  }
  return invalid;
}

// A seeded sample (with replacement) of at most max_candidates filtered points. Random rather
// than strided, so that the sample cannot alias with the sweep's beam-by-column point order.
void sample_candidates(const std::vector<Eigen::Vector3f>& filtered, std::size_t max_candidates,
                       std::mt19937_64& rng, std::vector<Eigen::Vector3f>& candidates) {
  candidates.clear();
  if (filtered.size() <= max_candidates) {
    candidates = filtered;
    return;
  }
  for (std::size_t i = 0; i < max_candidates; ++i) {
    candidates.push_back(filtered[draw_index(rng, filtered.size())]);
  }
}

// ---- 2. multi-start RANSAC with the MSAC score ---------------------------------------------

// Sum over the points of min(distance^2, truncation^2): lower is better.
double msac_score(const std::vector<Eigen::Vector3f>& points, const Plane& plane,
                  double truncation) {
  const Eigen::Vector3f n = plane.normal.cast<float>();
  const auto d = static_cast<float>(plane.offset);
  const auto t2 = static_cast<float>(truncation * truncation);
  float score = 0.0f;
  for (const Eigen::Vector3f& p : points) {
    const float r = n.dot(p) + d;
    score += std::min(r * r, t2);
  }
  return score;
}

// The plane through three points, oriented towards the origin, when it is a plausible road plane
// (within max_tilt of the LiDAR's z axis and min_height_m .. max_height_m below the LiDAR).
std::optional<Plane> plane_through(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                   const Eigen::Vector3f& c, const GroundOptions& options) {
  const Eigen::Vector3d ad = a.cast<double>();
  const Eigen::Vector3d cross = (b.cast<double>() - ad).cross(c.cast<double>() - ad);
  const double norm = cross.norm();
  if (!(norm > 1e-9)) return std::nullopt;  // collinear
  Plane plane{cross / norm, 0.0};
  plane.offset = -plane.normal.dot(ad);
  if (plane.offset < 0.0) plane = {-plane.normal, -plane.offset};
  if (plane.normal.z() < std::cos(options.max_tilt)) return std::nullopt;
  if (plane.offset < options.min_height_m || plane.offset > options.max_height_m) {
    return std::nullopt;
  }
  return plane;
}

struct ScoredPlane {
  Plane plane;
  double score = std::numeric_limits<double>::infinity();
};

// The paper's "RANSAC multiple times with random initial points": ransac_starts independent runs,
// each with its own stream; the best plane of all of them.
std::optional<ScoredPlane> multi_start_ransac(const std::vector<Eigen::Vector3f>& candidates,
                                              const GroundOptions& options, std::uint64_t seed) {
  std::optional<ScoredPlane> best;
  for (int start = 0; start < options.ransac_starts; ++start) {
    std::mt19937_64 rng(mix_seed(seed, 1000 + static_cast<std::uint64_t>(start)));
    for (int i = 0; i < options.ransac_iterations; ++i) {
      const std::size_t n = candidates.size();
      const std::size_t ia = draw_index(rng, n), ib = draw_index(rng, n), ic = draw_index(rng, n);
      if (ia == ib || ib == ic || ia == ic) continue;
      const auto plane = plane_through(candidates[ia], candidates[ib], candidates[ic], options);
      if (!plane) continue;
      const double score = msac_score(candidates, *plane, options.ransac_inlier_m);
      if (!best || score < best->score) best = ScoredPlane{*plane, score};
    }
  }
  return best;
}

// ---- 3. random search refinement -------------------------------------------------------------

ScoredPlane random_search(const std::vector<Eigen::Vector3f>& candidates, ScoredPlane best,
                          const GroundOptions& options, std::uint64_t seed) {
  std::mt19937_64 rng(mix_seed(seed, 2000));
  const double shrink = options.refine_steps > 1 ? std::pow(options.refine_final_fraction,
                                                            1.0 / (options.refine_steps - 1))
                                                 : 1.0;
  double angle_scale = options.refine_angle, offset_scale = options.refine_offset_m;
  const double cos_max_tilt = std::cos(options.max_tilt);
  for (int step = 0; step < options.refine_steps; ++step) {
    // Two unit vectors orthogonal to the normal: turning it by (a, b) radians about them.
    const Eigen::Vector3d& n = best.plane.normal;
    const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    const double a = angle_scale * draw_normal(rng), b = angle_scale * draw_normal(rng);
    Plane trial{(n + std::tan(a) * u + std::tan(b) * v).normalized(),
                best.plane.offset + offset_scale * draw_normal(rng)};
    angle_scale *= shrink;
    offset_scale *= shrink;
    if (trial.normal.z() < cos_max_tilt || trial.offset <= 0.0) continue;
    const double score = msac_score(candidates, trial, options.ransac_inlier_m);
    if (score < best.score) best = {trial, score};
  }
  return best;
}

// ---- 4. least-squares refit ------------------------------------------------------------------

struct Refit {
  Plane plane;
  std::size_t inliers = 0;
  double rms_m = 0.0;
};

// The total-least-squares plane of the filtered points within `distance` of `plane`: through the
// inliers' centroid, normal along the smallest eigenvector of their covariance. Sums are taken
// about the first inlier's foot on the plane to keep them well conditioned.
std::optional<Refit> refit_plane(const std::vector<Eigen::Vector3f>& filtered, const Plane& plane,
                                 double distance) {
  const Eigen::Vector3d origin = -plane.offset * plane.normal;  // the foot of the LiDAR's origin
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_outer = Eigen::Matrix3d::Zero();
  std::size_t count = 0;
  for (const Eigen::Vector3f& pf : filtered) {
    const Eigen::Vector3d p = pf.cast<double>();
    if (std::abs(plane.normal.dot(p) + plane.offset) > distance) continue;
    const Eigen::Vector3d q = p - origin;
    sum += q;
    sum_outer.noalias() += q * q.transpose();
    ++count;
  }
  if (count < 3) return std::nullopt;
  const Eigen::Vector3d mean = sum / static_cast<double>(count);
  const Eigen::Matrix3d covariance =
      sum_outer / static_cast<double>(count) - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  if (eigen.info() != Eigen::Success) return std::nullopt;
  Refit refit;
  refit.plane.normal = eigen.eigenvectors().col(0).normalized();
  refit.plane.offset = -refit.plane.normal.dot(mean + origin);
  if (refit.plane.offset < 0.0) refit.plane = {-refit.plane.normal, -refit.plane.offset};
  refit.inliers = count;
  refit.rms_m = std::sqrt(std::max(eigen.eigenvalues()(0), 0.0));
  return refit;
}

}  // namespace

void GroundOptions::Check() const {
  const OptionsCheck check("GroundOptions");
  check.non_negative("min_range_m", min_range_m);
  check.positive("max_range_m", max_range_m);
  check.that(min_range_m < max_range_m, "min_range_m", "must be < max_range_m", min_range_m);
  check.finite("max_lateral_m", max_lateral_m);  // <= 0 turns the limit off
  check.finite("travel_yaw", travel_yaw);
  check.non_negative("min_height_m", min_height_m);
  check.positive("max_height_m", max_height_m);
  check.that(min_height_m < max_height_m, "min_height_m", "must be < max_height_m", min_height_m);
  check.in_range("max_tilt", max_tilt, 0.0, kPi / 2.0, Bounds::kOpen);
  check.at_least("max_candidates", static_cast<double>(max_candidates), 3);
  check.at_least("ransac_starts", ransac_starts, 1);
  check.at_least("ransac_iterations", ransac_iterations, 1);
  check.positive("ransac_inlier_m", ransac_inlier_m);
  check.at_least("refine_steps", refine_steps, 0);
  check.in_range("refine_angle", refine_angle, 0.0, kPi / 4.0, Bounds::kOpenMax);
  check.non_negative("refine_offset_m", refine_offset_m);
  check.in_range("refine_final_fraction", refine_final_fraction, 0.0, 1.0, Bounds::kOpenMin);
  check.positive("refit_inlier_m", refit_inlier_m);
  check.in_range("min_refit_inlier_m", min_refit_inlier_m, 0.0, refit_inlier_m, Bounds::kOpenMin);
  check.positive("refit_rms_factor", refit_rms_factor);
  check.at_least("refit_passes", refit_passes, 1);
  check.at_least("min_inliers", static_cast<double>(min_inliers), 3);
  check.probability("min_inlier_fraction", min_inlier_fraction);
}

GroundFit fit_ground(const io::PointCloud& sweep, const GroundOptions& options,
                     std::uint64_t seed) {
  GroundScratch scratch;
  return fit_ground(sweep, options, seed, scratch);
}

GroundFit fit_ground(const io::PointCloud& sweep, const GroundOptions& options, std::uint64_t seed,
                     GroundScratch& scratch) {
  options.Check();
  GroundFit fit;
  fit.invalid_points = filter_points(sweep, options, scratch.filtered);
  const std::size_t filtered = scratch.filtered.size();
  if (filtered < options.min_inliers) {
    fit.failure = fmt::format(
        "only {} of {} points lie in the ground filter ({}-{} m away, {} m below the LiDAR); "
        "need {}",
        filtered, sweep.points.size(), options.min_range_m, options.max_range_m,
        options.min_height_m, options.min_inliers);
    return fit;
  }
  std::mt19937_64 sample_rng(mix_seed(seed, 0));
  sample_candidates(scratch.filtered, options.max_candidates, sample_rng, scratch.candidates);

  const std::optional<ScoredPlane> coarse = multi_start_ransac(scratch.candidates, options, seed);
  if (!coarse) {
    fit.failure = fmt::format("no RANSAC plane within {:.1f} deg of the LiDAR's z axis",
                              deg_from_rad(options.max_tilt));
    return fit;
  }
  const ScoredPlane refined = random_search(scratch.candidates, *coarse, options, seed);

  std::optional<Refit> refit;
  Plane plane = refined.plane;
  double band = options.refit_inlier_m;
  for (int pass = 0; pass < options.refit_passes; ++pass) {
    refit = refit_plane(scratch.filtered, plane, band);
    if (!refit) break;
    plane = refit->plane;
    band = std::clamp(options.refit_rms_factor * refit->rms_m, options.min_refit_inlier_m,
                      options.refit_inlier_m);
  }
  if (!refit || refit->plane.normal.z() < std::cos(options.max_tilt)) {
    fit.failure = "the least-squares refit of the RANSAC inliers left the tilt limit";
    return fit;
  }
  const auto needed = std::max(options.min_inliers,
                               static_cast<std::size_t>(std::ceil(options.min_inlier_fraction *
                                                                  static_cast<double>(filtered))));
  if (refit->inliers < needed) {
    fit.failure = fmt::format("the best plane has {} inliers of {} filtered points; need {}",
                              refit->inliers, filtered, needed);
    return fit;
  }
  fit.plane =
      GroundPlane{refit->plane.normal, refit->plane.offset, refit->inliers, filtered, refit->rms_m};
  return fit;
}

double roll_from_ground(const Eigen::Vector3d& normal_in_lidar) {
  return std::atan2(normal_in_lidar.y(), normal_in_lidar.z());
}

double pitch_from_ground(const Eigen::Vector3d& normal_in_lidar) {
  return std::asin(std::clamp(-normal_in_lidar.x() / normal_in_lidar.norm(), -1.0, 1.0));
}

}  // namespace x2car::lidar
