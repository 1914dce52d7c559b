// The position method's steps (radar_calibration.hpp; paper §III-D, "Refined calibration" with the
// vehicle position): straight stretches, objects grouped by track id (or by the association of
// radar_association.hpp when the radar reports none), the triangle test, a yaw from
// each pair of observations of a static object, the velocity-consistency confidence, and the robust
// weighted mean. Internal to x2car::radar.
//
// The paper's eq:radar_angle_1 (the triangle test) and eq:radar_angle_2 (psi from a pair) are
// estimate_pair's closure_m and yaw; position_method combines the pairs.
//
// Geometry of one pair, exact (no small-angle shortcut). Observations 0 and 1 of one object at
// ranges l0, l1 and azimuths th0, th1; between them the car turned by dh (INS yaw difference) and
// the radar moved by b in the car's frame at observation 0:
//   b = R(-yaw_ins(t0)) (odometry(t1) - odometry(t0)) + (R(dh) - I) t_V_R      (lever arm if given)
// A static point p in that frame satisfies p = R(psi) l0 u(th0) = b + R(dh) R(psi) l1 u(th1), so
//   w := l0 u(th0) - l1 u(th1 + dh) = R(-psi) b,   u(a) = (cos a, sin a).
// w is the point's apparent displacement seen from the radar (reversed), in radar coordinates.
//   Triangle test: the triangle of the two lines of sight and the baseline closes, |w| = |b| (the
//     paper's law-of-cosines test, written for the side |w|^2 = l0^2 + l1^2 - 2 l0 l1 cos(th0 - th1
//     - dh) instead of the angle, which is ill-conditioned when the angle is small: far targets,
//     targets dead ahead). A moving object's w also holds its own displacement and fails.
//   Yaw:  psi = atan2(b) - atan2(w), the exact form of the paper's psi1/psi2 (which take the angles
//     at the two ends from the ranges alone, unstable near dead ahead); defined whenever |w| > 0.
//   Confidence (paper): c = 1 - |v_r - v_r,static(psi)| / max(|v_r,static(psi)|, min_abs_cos |v|),
//     the relative error of the speed the Doppler implies, v_r,static the static-target range rate
//     of the radar's own velocity v (radar_velocity_method.hpp); averaged over the two
//     observations.
//   Weight: c / var(psi), var(psi) = var(w perpendicular to w) / |w|^2 from the nominal range and
//     azimuth noise.
// Speed scale: a static point's apparent displacement has the length of the true baseline, |w| =
// |b_true|, while the dead-reckoned b carries the INS speed's scale error k, |b| = k |b_true|; the
// median of |w| / |b| over the static objects' closing pairs is 1 / k. The baselines are multiplied
// by it and the triangle test run again (a few passes, until the ratio is within 0.1 % of 1), so a
// speed scale error neither rejects the static objects nor biases the test; the scale is reported
// (diagnostics.speed_scale = k) and checked. The pair yaws do not depend on it (the directions of
// b and w), except through the lever arm term.
// Nothing here assumes a direction of the radar: psi comes from the directions of b and w, the
// triangle test from their lengths, the confidence from the static model under psi_i, so a side
// or rear radar is handled as a front one (the pair yaws are averaged on the circle).
// Checks (docs/methods.md; RadarPositionMethodOptions): azimuths beyond +-pi or spanning a slit,
// the range rates against the static model (a flipped sign), the speed scale, the share of static
// objects, and the pairs' scatter against their predicted sigma; a failed check makes the result
// unreliable.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::radar {

// One object: the detections of one track id between breaks, in one straight stretch.
struct RadarObject {
  int track_id = io::kNoTrackId;
  std::vector<std::size_t> indices;  // into the samples, in time order
};

struct ObjectGrouping {
  std::vector<RadarObject> objects;  // every group, short ones included
  std::int64_t no_track_id = 0;      // detections without a track id
  std::int64_t off_straight = 0;     // detections outside the straight stretches
};

// `segment_of_sample`: the straight stretch each sample lies in, -1 for none. Samples in time
// order.
ObjectGrouping group_objects(std::span<const RadarSample> samples,
                             std::span<const int> segment_of_sample,
                             const RadarPositionMethodOptions& options);

struct PairEstimate {
  bool defined = false;     // false: no baseline or no apparent displacement (car standing: 0/0)
  double baseline_m = 0.0;  // |b| [m]
  double turn = 0.0;        // dh [rad]
  double closure_m = 0.0;   // |w| - |b| [m]
  double closure_sigma_m = 0.0;  // its predicted sigma [m]
  double yaw = 0.0;              // psi, in (-pi, pi] [rad]
  double yaw_sigma = 0.0;        // its predicted sigma [rad]
  double confidence = 0.0;       // c, clamped to [0, 1]
};

// The triangle of observations `first` and `second` (later) of one object, the car's displacement
// multiplied by `odometry_scale` (the estimated 1 / speed scale).
PairEstimate estimate_pair(const RadarSample& first, const RadarSample& second,
                           const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                           const RadarPositionMethodOptions& options, double odometry_scale = 1.0);

// The paper's velocity-consistency confidence of one observation under yaw `yaw`, in [0, 1].
double velocity_confidence(const RadarSample& sample, double yaw,
                           const RadarPositionMethodOptions& options);

// What the pairing left out, and the objects it kept.
struct PairCounts {
  std::int64_t short_tracks = 0;    // objects with fewer than min_observations detections
  std::int64_t short_baseline = 0;  // pairs
  std::int64_t turning_pair = 0;    // pairs
  std::int64_t moving_objects = 0;  // objects failing the triangle test
  std::int64_t not_closing = 0;     // pairs of static objects failing it
  std::int64_t low_confidence = 0;  // pairs below min_confidence
  std::int64_t static_objects = 0;
  std::int64_t objects = 0;  // with enough detections
  // The range-rate check (RadarPositionMethodOptions::min_range_rate_slope), over both detections
  // of every closing pair of a static object, under the pair's yaw: sums of v_r v_r,static and of
  // v_r,static^2 [m^2/s^2], and the pairs summed.
  double range_rate_dot = 0.0;
  double range_rate_norm = 0.0;
  std::int64_t closing_pairs = 0;
  // |w| / |b| of every closing pair of a static object: the dead reckoning's scale error shows as
  // their median's distance from 1.
  std::vector<double> displacement_ratios;
};

// The pairs' robust weighted mean (the paper averages the psi_i of eq:radar_angle_2).
struct Combination {
  double yaw = 0.0;               // [rad]
  double standard_error = 0.0;    // [rad]
  double normalised_sigma = 0.0;  // robust sigma of (psi_i - psi) / sigma_i: actual / nominal noise
  std::vector<std::uint8_t> inliers;
  std::int64_t outliers = 0;
  std::int64_t objects = 0;  // static objects with inlier pairs
};

// The position method's typed estimate: the counts at each step and, when it succeeded, the
// combination and the inlier pairs (their baselines, confidences, times and yaws).
struct RadarPositionEstimate {
  std::optional<std::string> insufficient_reason;  // set: the combination below is empty
  // Set when a check of the input or of the fit failed (docs/methods.md): the result is
  // unreliable, with the yaw when `combined`.
  std::optional<std::string> unreliable_reason;
  bool combined = false;  // the combination below holds the pairs' mean
  // The objects came from associating detections without track ids (radar_association.hpp), not
  // from the radar's ids; the associated tracks with two or more detections.
  bool associated = false;
  std::int64_t associated_tracks = 0;
  double azimuth_span = 0.0;  // of the detections, 5th to 95th percentile [rad]
  // The scale applied to the baselines, and the GNSS/INS speed's scale error found from the static
  // objects (reported speed / true speed; diagnostics.speed_scale), set when there were at least
  // min_pairs closing pairs (estimate_odometry_scale) [-].
  double odometry_scale = 1.0;
  std::optional<double> speed_scale;
  std::int64_t straight_segments = 0;
  std::int64_t no_track_id = 0;   // detections
  std::int64_t off_straight = 0;  // detections
  PairCounts counts;
  std::int64_t pairs = 0;  // usable pairs, before the outlier rejection
  Combination combination;
  std::vector<double> inlier_baselines_m;
  std::vector<double> inlier_confidences;
  std::vector<double> inlier_times;  // of each pair's later observation [s]
  std::vector<double> inlier_yaws;   // [rad]
};

// The whole method on gated samples (time order) with the per-record motion for the straight
// stretches. Samples without track ids are associated into tracks first
// (RadarPositionMethodOptions::associate_without_track_ids, always_associate).
RadarPositionEstimate estimate_yaw_by_position(
    std::span<const RadarSample> samples, std::span<const CarMotion> records,
    const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
    const RadarPositionMethodOptions& options);

// The estimate as a result with method "position": yaw and yaw_std, support (straight_segments,
// objects, static_objects, pairs, objects_with_pairs), rejections (no_track_id,
// off_straight_segments, short_tracks, moving_objects, short_baseline_pairs, turning_pairs,
// not_closing_pairs, low_confidence_pairs, outlier_pairs), diagnostics (median_baseline_m,
// median_confidence, noise_vs_nominal, range_rate_slope, speed_scale, static_object_fraction,
// azimuth_span_deg; associated 1 when the objects come from the association, with
// support.associated_tracks) and the pair_yaw series; or insufficient data with the reason and
// the counts; or unreliable (with the yaw when there is one) when a check failed.
CalibrationResult position_method_result(const RadarPositionEstimate& estimate);

// estimate_yaw_by_position written by position_method_result.
CalibrationResult position_method(std::span<const RadarSample> samples,
                                  std::span<const CarMotion> records,
                                  const std::optional<Eigen::Vector2d>& lever_arm_in_vehicle,
                                  const RadarPositionMethodOptions& options);

}  // namespace x2car::radar
