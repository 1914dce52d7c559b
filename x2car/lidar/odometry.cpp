#include "x2car/lidar/odometry.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/lidar/registration.hpp"

namespace x2car::lidar {

void OdometryOptions::Check() const {
  const OptionsCheck check("OdometryOptions");
  check.positive("max_range_m", max_range_m);
  check.in_range("min_range_m", min_range_m, 0.0, max_range_m, Bounds::kOpenMax);
  check.positive("voxel_size_m", voxel_size_m);
  check.in_range("max_points_per_voxel", max_points_per_voxel, 1, 65535);
  check.positive("initial_threshold_m", initial_threshold_m);
  check.non_negative("min_motion_m", min_motion_m);
  check.positive("kernel_scale_factor", kernel_scale_factor);
  check.non_negative("point_to_point_weight", point_to_point_weight);
  check.at_least("max_iterations", max_iterations, 1);
  check.positive("convergence", convergence);
  check.positive("max_sweep_span_s", max_sweep_span_s);
  check.at_least("max_final_update", max_final_update, convergence);
  check.at_least("min_points", static_cast<double>(min_points), 6);
  check.in_range("min_translation_constraint", min_translation_constraint, 0.0, 1.0 / 3.0);
  check.in_range("min_rotation_constraint", min_rotation_constraint, 0.0, 1.0 / 3.0);
  check.at_least("degeneracy_samples", static_cast<double>(degeneracy_samples), 1);
  check.positive("max_speed_mps", max_speed_mps);
  check.positive("max_angular_rate", max_angular_rate);
  planarity.Check();
}

constexpr std::array<EnumName<RegistrationStatus>, 6> kRegistrationStatusNames{{
    {RegistrationStatus::kFirstSweep, "first_sweep"},
    {RegistrationStatus::kOk, "ok"},
    {RegistrationStatus::kTooFewPoints, "too_few_points"},
    {RegistrationStatus::kNotConverged, "not_converged"},
    {RegistrationStatus::kDegenerate, "degenerate"},
    {RegistrationStatus::kImplausibleMotion, "implausible_motion"},
}};

std::string to_string(RegistrationStatus status) {
  return enum_to_string(kRegistrationStatusNames, status);
}

LidarOdometry::LidarOdometry(const OdometryOptions& options)
    : options_((options.Check(), options)),
      map_(static_cast<float>(options.voxel_size_m), options.max_points_per_voxel),
      threshold_(options.initial_threshold_m, options.max_range_m, options.min_motion_m) {}

void LidarOdometry::preprocess(const io::PointCloud& sweep, OdometryStep& step) {
  const float min_range2 = static_cast<float>(options_.min_range_m * options_.min_range_m);
  const float max_range2 = static_cast<float>(options_.max_range_m * options_.max_range_m);
  frame_.clear();
  frame_times_.clear();
  // Filtering and the first downsampling in one pass over the ~100 k points.
  fine_downsampler_.start(0.5f * static_cast<float>(options_.voxel_size_m));
  float t_min = std::numeric_limits<float>::infinity();
  float t_max = -std::numeric_limits<float>::infinity();
  for (const io::LidarPoint& p : sweep.points) {
    const Eigen::Vector3f point(p.x, p.y, p.z);
    // A NaN time would deskew the point to NaN, and NaN has no voxel.
    if (!point.allFinite() || (sweep.has_time && !std::isfinite(p.t))) {
      ++step.invalid_points;
      continue;
    }
    const float range2 = point.squaredNorm();
    if (range2 < min_range2 || range2 > max_range2) continue;
    ++step.points_in_range;
    t_min = std::min(t_min, p.t);
    t_max = std::max(t_max, p.t);
    if (fine_downsampler_.keep(point)) {
      frame_.push_back(point);
      frame_times_.push_back(p.t);
    }
  }
  // Times spanning more than a sweep can last are in another unit or broken: deskewing along them
  // would throw the points far away, so the sweep is taken as it is.
  if (!sweep.has_time || frame_.empty() || !(t_max - t_min <= options_.max_sweep_span_s)) {
    return;
  }
  step.deskew_time_s = 0.5 * (static_cast<double>(t_min) + static_cast<double>(t_max));
  // Deskewing needs a velocity, which the first two sweeps do not have yet.
  if (!options_.deskew || sweeps_ < 2) return;
  const ScrewMotion motion(twist_per_second_);
  const float reference = static_cast<float>(step.deskew_time_s);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frame_.size(), 2048),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        frame_[i] = motion.apply(frame_[i], frame_times_[i] - reference);
                      }
                    });
  step.deskewed = true;
}

Eigen::Isometry3d LidarOdometry::predict(double time) const {
  if (sweeps_ == 0) return Eigen::Isometry3d::Identity();
  return last_pose_ * se3_exp(twist_per_second_ * (time - last_time_));
}

RegistrationStatus LidarOdometry::judge(const OdometryStep& step, double last_update,
                                        const Eigen::Isometry3d& estimate) const {
  if (step.points_used < options_.min_points) return RegistrationStatus::kTooFewPoints;
  if (!(last_update <= options_.max_final_update)) return RegistrationStatus::kNotConverged;
  if (step.translation_constraint < options_.min_translation_constraint ||
      step.rotation_constraint < options_.min_rotation_constraint) {
    return RegistrationStatus::kDegenerate;
  }
  const Eigen::Isometry3d motion = last_pose_.inverse() * estimate;
  const double dt = step.time - last_time_;
  if (motion.translation().norm() > options_.max_speed_mps * dt ||
      Eigen::AngleAxisd(motion.linear()).angle() > options_.max_angular_rate * dt) {
    return RegistrationStatus::kImplausibleMotion;
  }
  return RegistrationStatus::kOk;
}

OdometryStep LidarOdometry::register_sweep(const io::PointCloud& sweep, double sweep_time) {
  OdometryStep step;
  preprocess(sweep, step);
  step.time = sweep_time + step.deskew_time_s;
  if (sweeps_ > 0 && !(step.time > last_time_)) {
    throw std::invalid_argument("LidarOdometry::register_sweep: sweep times must increase");
  }
  const float voxel_size = static_cast<float>(options_.voxel_size_m);
  coarse_downsampler_.downsample(frame_, 1.5f * voxel_size, source_, &source_of_frame_);
  step.source_points = source_.size();
  planar_normals(frame_, source_of_frame_, source_, options_.planarity, moments_, source_normals_);

  const Eigen::Isometry3d prediction = predict(step.time);
  step.world_from_lidar = prediction;
  const double sigma = threshold_.sigma();
  step.threshold_m = 3.0 * sigma;
  if (source_.size() < options_.min_points) {
    step.status = RegistrationStatus::kTooFewPoints;
  } else if (map_.empty()) {
    step.status = RegistrationStatus::kFirstSweep;
  } else {
    IcpSettings settings;
    settings.max_correspondence_distance = step.threshold_m;
    settings.kernel_scale = options_.kernel_scale_factor * sigma;
    settings.point_to_point_weight = options_.point_to_point_weight;
    settings.max_iterations = options_.max_iterations;
    settings.convergence = options_.convergence;
    neighbourhoods_.assign(source_.size(), VoxelHashMap::Neighbourhood{});
    const IcpResult icp =
        align_to_map(source_, source_normals_, map_, prediction, settings, neighbourhoods_);
    step.iterations = icp.iterations;
    step.points_used = icp.correspondences;
    step.rms_residual_m = icp.rms_residual;
    const ConstraintStrength strength =
        constraint_strength(source_, map_, icp.world_from_source, options_.degeneracy_samples);
    step.translation_constraint = strength.translation;
    step.rotation_constraint = strength.rotation;
    step.status = judge(step, icp.converged ? 0.0 : icp.last_update, icp.world_from_source);
    if (step.status == RegistrationStatus::kOk) {
      step.world_from_lidar = icp.world_from_source;
      threshold_.update(prediction.inverse() * icp.world_from_source);
    }
  }

  // The map grows from every sweep, at the best pose there is: a sweep that failed to register is
  // placed at its prediction, so that the map follows the car until matching resumes.
  const Eigen::Matrix3f rotation = step.world_from_lidar.linear().cast<float>();
  const Eigen::Vector3f translation = step.world_from_lidar.translation().cast<float>();
  for (Eigen::Vector3f& p : frame_) p = rotation * p + translation;
  map_.add_points(frame_);
  map_.remove_far_from(translation, static_cast<float>(options_.max_range_m));

  if (sweeps_ > 0) {
    twist_per_second_ =
        se3_log(last_pose_.inverse() * step.world_from_lidar) / (step.time - last_time_);
  }
  last_pose_ = step.world_from_lidar;
  last_time_ = step.time;
  ++sweeps_;
  return step;
}

}  // namespace x2car::lidar
