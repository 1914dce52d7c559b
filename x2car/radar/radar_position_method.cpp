#include "x2car/radar/radar_position_method.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/segmentation.hpp"
#include "x2car/radar/radar_association.hpp"
#include "x2car/radar/radar_position_checks.hpp"
#include "x2car/radar/radar_velocity_method.hpp"

namespace x2car::radar {
namespace {

Eigen::Vector2d perpendicular(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

Eigen::Vector2d rotate(double angle, const Eigen::Vector2d& v) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// The odometry scale's estimate (estimate_yaw_by_position): at most this many passes, stopping
// when the median ratio is within kScaleConvergence of 1, and kept within what no speed sensor is
// off by.
constexpr int kScalePasses = 4;
constexpr double kScaleConvergence = 1e-3;
constexpr double kMinOdometryScale = 0.75;
constexpr double kMaxOdometryScale = 1.33;

// Straight stretches of the drive, judged at the GNSS/INS records (curvature = yaw rate / speed),
// and the stretch each sample falls in (-1: none).
struct StraightStretches {
  Segmentation segmentation;
  std::vector<int> segment_of_sample;
};

StraightStretches straight_stretches(std::span<const RadarSample> samples,
                                     std::span<const CarMotion> records,
                                     const SegmentationOptions& options) {
  std::vector<double> times(records.size());
  std::vector<double> speeds(records.size());
  std::vector<double> curvatures(records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    times[i] = records[i].time;
    speeds[i] = std::abs(records[i].speed_mps);
    curvatures[i] = speeds[i] > 0.0 ? records[i].yaw_rate / speeds[i] : 0.0;
  }
  StraightStretches stretches;
  stretches.segmentation = segment_runs(times, speeds, curvatures, options);
  const std::vector<TimeSegment>& segments = stretches.segmentation.segments;
  stretches.segment_of_sample.assign(samples.size(), -1);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto after = std::upper_bound(
        segments.begin(), segments.end(), samples[i].time,
        [](double time, const TimeSegment& segment) { return time < segment.start_time; });
    if (after == segments.begin()) continue;
    const auto index = static_cast<int>(after - segments.begin()) - 1;
    if (samples[i].time <= segments[static_cast<std::size_t>(index)].end_time) {
      stretches.segment_of_sample[i] = index;
    }
  }
  return stretches;
}

// Whether `next` can be the same target as `last` one scan or a few later: the range moved as the
// range rate says, and the point did not move across the line of sight impossibly fast.
bool continues_track(const RadarSample& last, const RadarSample& next,
                     const RadarPositionMethodOptions& options) {
  const double dt = next.time - last.time;
  if (next.new_track || dt > options.max_track_gap_s) return false;
  const double expected_range = last.range + 0.5 * (last.range_rate + next.range_rate) * dt;
  if (std::abs(next.range - expected_range) > options.max_range_jump_m) return false;
  const double cross_range =
      std::min(last.range, next.range) * std::abs(angle_difference(next.azimuth, last.azimuth));
  return cross_range <= options.max_range_jump_m + options.max_relative_speed_mps * dt;
}

// Variance of the component of w along `direction` (unit), from the nominal range and azimuth
// noise of both observations (radar_position_method.hpp).
double apparent_variance_along(const Eigen::Vector2d& direction, double range0, double azimuth0,
                               double range1, double azimuth1,
                               const RadarPositionMethodOptions& options) {
  const Eigen::Vector2d a = unit_vector(azimuth0);
  const Eigen::Vector2d b = unit_vector(azimuth1);
  const double range_var = options.range_sigma_m * options.range_sigma_m;
  const double azimuth_var = options.azimuth_sigma * options.azimuth_sigma;
  const double along_a = perpendicular(a).dot(direction);
  const double along_b = perpendicular(b).dot(direction);
  return range_var * (std::pow(a.dot(direction), 2) + std::pow(b.dot(direction), 2)) +
         azimuth_var * (range0 * range0 * along_a * along_a + range1 * range1 * along_b * along_b);
}

// Inverse-variance weighted mean of angles around `reference` [rad], in (-pi, pi].
double weighted_mean_angle(std::span<const double> angles, std::span<const double> weights,
                           double reference) {
  std::vector<double> deviations(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    deviations[i] = angle_difference(angles[i], reference);
  }
  return wrap_angle(reference + weighted_mean(deviations, weights));
}

// One usable pair of a static object.
struct PairRecord {
  double time = 0.0;  // of the later observation [s]
  std::size_t object = 0;
  PairEstimate estimate;
  double weight = 0.0;  // c / var(psi)
};

// Pairs observation j with j + n/2: every detection is used once, so the pairs' errors are
// independent (pairing all with the first, as the paper does, shares the first's error), and the
// baselines are half the track, long enough for a well-shaped triangle.
std::vector<PairRecord> static_object_pairs(std::span<const RadarSample> samples,
                                            std::span<const RadarObject> objects,
                                            const std::optional<Eigen::Vector2d>& lever_arm,
                                            const RadarPositionMethodOptions& options,
                                            double odometry_scale, PairCounts& counts) {
  const double max_turn = lever_arm ? options.max_pair_turn_with_lever_arm : options.max_pair_turn;
  std::vector<PairRecord> pairs;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const std::vector<std::size_t>& indices = objects[k].indices;
    if (static_cast<int>(indices.size()) < options.min_observations) {
      ++counts.short_tracks;
      continue;
    }
    ++counts.objects;
    const std::size_t half = indices.size() / 2;
    std::vector<PairEstimate> usable;
    for (std::size_t j = 0; j + half < indices.size(); ++j) {
      const PairEstimate estimate = estimate_pair(samples[indices[j]], samples[indices[j + half]],
                                                  lever_arm, options, odometry_scale);
      if (!estimate.defined || estimate.baseline_m < options.min_baseline_m) {
        ++counts.short_baseline;
      } else if (std::abs(estimate.turn) > max_turn) {
        ++counts.turning_pair;
      } else {
        usable.push_back(estimate);
      }
    }
    if (usable.empty()) continue;
    const auto closes = [&](const PairEstimate& e) {
      return std::abs(e.closure_m) <= options.triangle_sigmas * e.closure_sigma_m;
    };
    const auto closing = std::count_if(usable.begin(), usable.end(), closes);
    if (static_cast<double>(closing) <
        options.min_static_fraction * static_cast<double>(usable.size())) {
      ++counts.moving_objects;
      continue;
    }
    ++counts.static_objects;
    for (std::size_t j = 0; j < usable.size(); ++j) {
      if (closes(usable[j])) {
        for (const std::size_t i : {indices[j], indices[j + half]}) {
          const double expected = static_range_rate(samples[i], usable[j].yaw);
          counts.range_rate_dot += samples[i].range_rate * expected;
          counts.range_rate_norm += expected * expected;
        }
        ++counts.closing_pairs;
        counts.displacement_ratios.push_back(1.0 + usable[j].closure_m / usable[j].baseline_m);
      }
      if (!closes(usable[j])) {
        ++counts.not_closing;
      } else if (usable[j].confidence < options.min_confidence) {
        ++counts.low_confidence;
      } else {
        pairs.push_back(
            {.time = samples[indices[j + half]].time,
             .object = k,
             .estimate = usable[j],
             .weight = usable[j].confidence / (usable[j].yaw_sigma * usable[j].yaw_sigma)});
      }
    }
  }
  return pairs;
}

// Robust weighted mean: reject pairs far from the mean in units of their own sigma, scaled by the
// robust spread of the normalised residuals (the nominal noise may be off), and iterate.
Combination combine_pairs(std::span<const PairRecord> pairs,
                          const RadarPositionMethodOptions& options) {
  std::vector<double> yaws(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) yaws[i] = pairs[i].estimate.yaw;
  Combination combination;
  combination.yaw = yaws[0] + median([&] {
                      std::vector<double> d(yaws.size());
                      for (std::size_t i = 0; i < yaws.size(); ++i) {
                        d[i] = angle_difference(yaws[i], yaws[0]);
                      }
                      return d;
                    }());
  combination.inliers.assign(pairs.size(), 1);
  for (int iteration = 0; iteration < 5; ++iteration) {
    std::vector<double> normalised(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      normalised[i] = angle_difference(yaws[i], combination.yaw) / pairs[i].estimate.yaw_sigma;
    }
    combination.normalised_sigma = std::max(robust_sigma(normalised), 1e-3);
    std::vector<double> kept;
    std::vector<double> weights;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      combination.inliers[i] =
          std::abs(normalised[i]) <= options.outlier_sigmas * combination.normalised_sigma;
      if (!combination.inliers[i]) continue;
      kept.push_back(yaws[i]);
      weights.push_back(pairs[i].weight);
    }
    if (kept.empty()) break;
    combination.yaw = weighted_mean_angle(kept, weights, combination.yaw);
  }
  // Standard error: the sandwich form over independent pairs, and over objects (errors an object
  // shares, e.g. a reflector that is not a point); the larger.
  std::vector<double> deviations;
  std::vector<double> weights;
  std::map<std::size_t, std::pair<double, double>> per_object;  // sum w d, sum w
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!combination.inliers[i]) {
      ++combination.outliers;
      continue;
    }
    const double deviation = angle_difference(yaws[i], combination.yaw);
    deviations.push_back(deviation);
    weights.push_back(pairs[i].weight);
    auto& [sum_wd, sum_w] = per_object[pairs[i].object];
    sum_wd += pairs[i].weight * deviation;
    sum_w += pairs[i].weight;
  }
  combination.objects = static_cast<std::int64_t>(per_object.size());
  if (deviations.size() >= 2) {
    combination.standard_error = standard_error_of_weighted_mean(deviations, weights);
  }
  if (static_cast<int>(per_object.size()) >= std::max(options.min_objects_for_spread, 2)) {
    std::vector<double> object_means;
    std::vector<double> object_weights;
    for (const auto& [object, sums] : per_object) {
      object_means.push_back(sums.first / sums.second);
      object_weights.push_back(sums.second);
    }
    combination.standard_error = std::max(
        combination.standard_error, standard_error_of_weighted_mean(object_means, object_weights));
  }
  return combination;
}

// Samples with the association's track ids in place of the radar's (none).
std::vector<RadarSample> with_associated_tracks(std::span<const RadarSample> samples,
                                                const RadarPositionMethodOptions& options,
                                                std::int64_t& tracks) {
  const RadarAssociation association = associate_detections(samples, options);
  std::vector<RadarSample> associated(samples.begin(), samples.end());
  for (std::size_t i = 0; i < associated.size(); ++i) {
    associated[i].track_id = association.track_of_sample[i];
    associated[i].new_track = false;
  }
  tracks = association.tracks_of_two_or_more;
  return associated;
}

}  // namespace

ObjectGrouping group_objects(std::span<const RadarSample> samples,
                             std::span<const int> segment_of_sample,
                             const RadarPositionMethodOptions& options) {
  ObjectGrouping grouping;
  std::map<int, std::size_t> open;  // track id -> its current object
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const RadarSample& sample = samples[i];
    if (sample.track_id == io::kNoTrackId) {
      ++grouping.no_track_id;
      continue;
    }
    if (segment_of_sample[i] < 0) {
      ++grouping.off_straight;
      open.erase(sample.track_id);
      continue;
    }
    const auto found = open.find(sample.track_id);
    if (found != open.end()) {
      RadarObject& object = grouping.objects[found->second];
      const std::size_t last = object.indices.back();
      if (segment_of_sample[last] == segment_of_sample[i] &&
          continues_track(samples[last], sample, options)) {
        object.indices.push_back(i);
        continue;
      }
    }
    open[sample.track_id] = grouping.objects.size();
    grouping.objects.push_back({.track_id = sample.track_id, .indices = {i}});
  }
  return grouping;
}

PairEstimate estimate_pair(const RadarSample& first, const RadarSample& second,
                           const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                           const RadarPositionMethodOptions& options, double odometry_scale) {
  PairEstimate estimate;
  estimate.turn = second.ins_yaw_unwrapped - first.ins_yaw_unwrapped;
  // b: the radar's displacement in the car's frame at the first observation.
  Eigen::Vector2d baseline =
      odometry_scale * rotate(-first.ins_yaw_unwrapped, second.odometry - first.odometry);
  if (lever_arm_in_vehicle) {
    baseline += rotate(estimate.turn, *lever_arm_in_vehicle) - *lever_arm_in_vehicle;
  }
  const Eigen::Vector2d apparent = first.range * unit_vector(first.azimuth) -
                                   second.range * unit_vector(second.azimuth + estimate.turn);
  estimate.baseline_m = baseline.norm();
  const double apparent_m = apparent.norm();
  // Car standing or a target that kept its place in the radar's view: no triangle, psi is 0/0.
  if (!(estimate.baseline_m > 0.0) || !(apparent_m > 0.0)) return estimate;
  estimate.defined = true;
  const Eigen::Vector2d along = apparent / apparent_m;
  const double odometry_sigma = options.odometry_sigma_fraction * estimate.baseline_m;
  const double azimuth1 = second.azimuth + estimate.turn;
  estimate.closure_m = apparent_m - estimate.baseline_m;
  estimate.closure_sigma_m = std::sqrt(
      apparent_variance_along(along, first.range, first.azimuth, second.range, azimuth1, options) +
      odometry_sigma * odometry_sigma);
  estimate.yaw_sigma =
      std::sqrt(apparent_variance_along(perpendicular(along), first.range, first.azimuth,
                                        second.range, azimuth1, options)) /
      apparent_m;
  estimate.yaw_sigma = std::max(estimate.yaw_sigma, 1e-6);
  estimate.yaw = angle_difference(std::atan2(baseline.y(), baseline.x()),
                                  std::atan2(apparent.y(), apparent.x()));
  estimate.confidence = 0.5 * (velocity_confidence(first, estimate.yaw, options) +
                               velocity_confidence(second, estimate.yaw, options));
  return estimate;
}

double velocity_confidence(const RadarSample& sample, double yaw,
                           const RadarPositionMethodOptions& options) {
  const double speed = sample.radar_velocity_in_vehicle.norm();
  if (!(speed > 0.0)) return 0.0;  // car standing: the Doppler says nothing
  const double expected = static_range_rate(sample, yaw);
  const double scale = std::max(std::abs(expected), options.min_abs_cos * speed);
  return std::clamp(1.0 - std::abs(sample.range_rate - expected) / scale, 0.0, 1.0);
}

RadarPositionEstimate estimate_yaw_by_position(
    std::span<const RadarSample> samples, std::span<const CarMotion> records,
    const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
    const RadarPositionMethodOptions& options) {
  RadarPositionEstimate estimate;
  estimate.azimuth_span = azimuth_span(samples);
  if (auto failed = check_azimuths(samples, estimate.azimuth_span, options)) {
    estimate.unreliable_reason = std::move(failed);
    return estimate;
  }
  // Objects by the radar's track ids, or by associating the detections when it has none.
  const bool has_track_ids = std::any_of(samples.begin(), samples.end(), [](const RadarSample& s) {
    return s.track_id != io::kNoTrackId;
  });
  std::vector<RadarSample> associated;
  if (options.always_associate || (!has_track_ids && options.associate_without_track_ids)) {
    associated = with_associated_tracks(samples, options, estimate.associated_tracks);
    estimate.associated = true;
    samples = associated;
  }
  const StraightStretches stretches = straight_stretches(samples, records, options.straight);
  estimate.straight_segments = static_cast<std::int64_t>(stretches.segmentation.segments.size());
  const ObjectGrouping grouping = group_objects(samples, stretches.segment_of_sample, options);
  estimate.no_track_id = grouping.no_track_id;
  estimate.off_straight = grouping.off_straight;
  // The dead reckoning's scale (the INS speed's scale error): the static objects' apparent
  // displacements |w| against the baselines |b|, their median ratio applied to the baselines and
  // estimated again until it stops changing (radar_position_method.hpp).
  std::vector<PairRecord> pairs;
  for (int pass = 0; pass < kScalePasses; ++pass) {
    estimate.counts = {};
    pairs = static_object_pairs(samples, grouping.objects, lever_arm_in_vehicle, options,
                                estimate.odometry_scale, estimate.counts);
    if (!options.estimate_odometry_scale || estimate.counts.closing_pairs < options.min_pairs) {
      break;
    }
    const double ratio = median(estimate.counts.displacement_ratios);
    estimate.speed_scale = 1.0 / (estimate.odometry_scale * ratio);
    if (std::abs(ratio - 1.0) < kScaleConvergence) break;
    estimate.odometry_scale =
        std::clamp(estimate.odometry_scale * ratio, kMinOdometryScale, kMaxOdometryScale);
  }
  estimate.pairs = static_cast<std::int64_t>(pairs.size());
  estimate.unreliable_reason = check_pairs(estimate.counts, estimate.speed_scale, options);
  if (samples.empty()) {
    estimate.insufficient_reason = "no radar detections left for the position method";
    return estimate;
  }
  if (grouping.no_track_id == static_cast<std::int64_t>(samples.size())) {
    estimate.insufficient_reason =
        "the radar detections carry no track ids and the association is off "
        "(associate_without_track_ids); the position method groups by track id";
    return estimate;
  }
  if (stretches.segmentation.segments.empty()) {
    estimate.insufficient_reason =
        fmt::format("no straight stretch of at least {:.1f} s above {:.1f} m/s in the GNSS/INS log",
                    options.straight.min_duration_s, options.straight.min_speed);
    return estimate;
  }
  const PairCounts& counts = estimate.counts;
  if (counts.static_objects < options.min_static_objects ||
      static_cast<int>(pairs.size()) < options.min_pairs) {
    estimate.insufficient_reason = fmt::format(
        "only {} static objects and {} usable observation pairs (baseline >= {:.1f} m); need {} "
        "and {} ({} pairs had a shorter baseline, {} objects failed the triangle test)",
        counts.static_objects, pairs.size(), options.min_baseline_m, options.min_static_objects,
        options.min_pairs, counts.short_baseline, counts.moving_objects);
    return estimate;
  }
  estimate.combination = combine_pairs(pairs, options);
  const Combination& combination = estimate.combination;
  if (!estimate.unreliable_reason && combination.normalised_sigma > options.max_noise_vs_nominal) {
    estimate.unreliable_reason = fmt::format(
        "the pair yaws scatter {:.1f} times their predicted sigma (need <= {:.1f}): the radar is "
        "far noisier than its nominal noise, or the objects are not what the triangles assume",
        combination.normalised_sigma, options.max_noise_vs_nominal);
  }
  if (static_cast<int>(pairs.size()) - combination.outliers < options.min_pairs) {
    estimate.insufficient_reason =
        fmt::format("only {} of {} observation pairs agree with each other; need {}",
                    static_cast<std::int64_t>(pairs.size()) - combination.outliers, pairs.size(),
                    options.min_pairs);
    return estimate;
  }
  estimate.combined = true;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!combination.inliers[i]) continue;
    estimate.inlier_baselines_m.push_back(pairs[i].estimate.baseline_m);
    estimate.inlier_confidences.push_back(pairs[i].estimate.confidence);
    estimate.inlier_times.push_back(pairs[i].time);
    estimate.inlier_yaws.push_back(pairs[i].estimate.yaw);
  }
  return estimate;
}

namespace {

// The result's figures and status without the checks' verdict.
CalibrationResult position_method_figures(const RadarPositionEstimate& estimate) {
  CalibrationResult result;
  if (estimate.insufficient_reason || !estimate.combined) {
    result = insufficient_data("radar", estimate.insufficient_reason.value_or(""));
  } else {
    result.sensor = "radar";
    result.status = CalibrationStatus::kOk;
  }
  result.method = "position";
  const PairCounts& counts = estimate.counts;
  result.rejections = {{"no_track_id", estimate.no_track_id},
                       {"off_straight_segments", estimate.off_straight},
                       {"short_tracks", counts.short_tracks},
                       {"moving_objects", counts.moving_objects},
                       {"short_baseline_pairs", counts.short_baseline},
                       {"turning_pairs", counts.turning_pair},
                       {"not_closing_pairs", counts.not_closing},
                       {"low_confidence_pairs", counts.low_confidence}};
  result.support = {{"straight_segments", estimate.straight_segments},
                    {"objects", counts.objects},
                    {"static_objects", counts.static_objects},
                    {"pairs", estimate.pairs}};
  result.diagnostics = {{"azimuth_span_deg", deg_from_rad(estimate.azimuth_span)},
                        {"associated", estimate.associated ? 1.0 : 0.0}};
  if (estimate.associated) result.support["associated_tracks"] = estimate.associated_tracks;
  if (counts.closing_pairs > 0) {
    result.diagnostics["range_rate_slope"] = range_rate_slope(counts);
    if (estimate.speed_scale) result.diagnostics["speed_scale"] = *estimate.speed_scale;
  }
  if (counts.static_objects + counts.moving_objects > 0) {
    result.diagnostics["static_object_fraction"] = static_object_fraction(counts);
  }
  if (!estimate.combined) return result;
  const Combination& combination = estimate.combination;
  result.yaw = combination.yaw;
  result.yaw_std = combination.standard_error;
  result.rejections["outlier_pairs"] = combination.outliers;
  result.support["pairs"] = estimate.pairs - combination.outliers;
  result.support["objects_with_pairs"] = combination.objects;
  result.diagnostics["median_baseline_m"] = median(estimate.inlier_baselines_m);
  result.diagnostics["median_confidence"] = median(estimate.inlier_confidences);
  result.diagnostics["noise_vs_nominal"] = combination.normalised_sigma;
  result.series.push_back({"pair_yaw", "rad", estimate.inlier_times, estimate.inlier_yaws});
  return result;
}

}  // namespace

CalibrationResult position_method_result(const RadarPositionEstimate& estimate) {
  CalibrationResult result = position_method_figures(estimate);
  if (estimate.unreliable_reason) {
    std::string reason = *estimate.unreliable_reason;
    if (estimate.insufficient_reason) reason += "; also " + *estimate.insufficient_reason;
    result = mark_unreliable(std::move(result), std::move(reason));
  }
  return result;
}

CalibrationResult position_method(std::span<const RadarSample> samples,
                                  std::span<const CarMotion> records,
                                  const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                                  const RadarPositionMethodOptions& options) {
  return position_method_result(
      estimate_yaw_by_position(samples, records, lever_arm_in_vehicle, options));
}

}  // namespace x2car::radar
