// Radar -> car: the mounting yaw of a 2-D radar from its detections and the GNSS/INS log (DESIGN
// §2, paper §III-D). Roll and pitch are not observable by a 2-D radar and are reported as null.
//
// Sign convention (io/radar_csv.hpp): range_rate is d range / dt, NEGATIVE when the target
// approaches; azimuth is counter-clockwise from the radar's boresight. A static target seen at
// azimuth theta by a radar with mounting yaw psi whose velocity over ground in the vehicle frame
// is (v_x, v_y) has
//   range_rate = -(v_x cos(theta + psi) + v_y sin(theta + psi)),
// which for a car driving straight at speed v is range_rate = -v cos(theta + psi). psi is the yaw
// of vehicle_from_radar relative to the car's direction of motion (its x axis, by the
// non-holonomic constraint; radar_ego_motion.hpp).
//
// Velocity method (the paper's primary): keep detections taken while the car moves at least
// min_speed_mps (and, without the radar's lever arm, while it does not turn); coarse search of
// (psi, speed scale s) over the full circle (or around nominal_yaw), counting detections within
// coarse_tolerance_mps of the static model; then iterate: select the detections consistent with
// the static model (an adaptive k-sigma gate), fit (psi, s) by Gauss-Newton with Huber weights
// within max_refinement_move of the coarse optimum, until they stop moving. The standard error is
// block-clustered over time (correlated detections) with a Student-t factor; the fit's checks
// (residual spread, static fraction, speed scale, basin, windows, static targets moving as fitted)
// make a failed fit `unreliable` (radar_velocity_checks.hpp, docs/methods.md).
//
// Position method (the paper's refinement for noisy radars; radar_position_method.hpp): on straight
// stretches, detections grouped into objects by track id; objects whose range/azimuth history is a
// static point seen from the moving car (triangle test) give psi from pairs of observations,
// weighted by the velocity-consistency confidence and their predicted precision.
// kAuto runs both and reports one, chosen by agreement and support (radar_auto.hpp); the result's
// method names it, its reason says why, and both methods' figures are in diagnostics and support.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/segmentation.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/radar_csv.hpp"

namespace x2car::radar {

enum class RadarMethod { kAuto, kVelocity, kPosition };

// "auto", "velocity", "position"; parsing throws std::invalid_argument listing the names.
const char* to_string(RadarMethod method);
RadarMethod radar_method_from_string(const std::string& text);
std::vector<std::string> radar_method_names();  // "auto", "velocity", "position": the CLI's choices

struct RadarVelocityMethodOptions {
  // Coarse search (docs/methods.md "Velocity method"). Without a prior, psi over the full circle:
  // the cosine model has no 180 deg ambiguity once the ego speed is known, so side- and
  // rear-facing radars need no guess. With `nominal_yaw` (the mounting as designed, e.g. from a
  // drawing or a tf tree), psi over [nominal_yaw - A, nominal_yaw + A] only.
  std::optional<double> nominal_yaw;              // [rad]
  double search_half_range = rad_from_deg(45.0);  // A around nominal_yaw (paper: 45 deg) [rad]
  // Grid step of the coarse search. The paper uses 5 deg; the count is computed here for every
  // grid value at once (each detection adds the arcs of psi where it fits), so a fine grid costs
  // nothing [rad].
  double search_step = rad_from_deg(0.5);
  // A detection counts as consistent with the static model in the coarse search within this
  // range-rate tolerance; wide enough for half a scale step of model error at urban speeds [m/s].
  double coarse_tolerance_mps = 0.5;
  // The coarse search counts every k-th detection when there are more than this.
  int max_coarse_detections = 20000;
  // The refinement stays in the coarse optimum's basin: psi may move at most this far from it;
  // a fit that ends on this bound is unreliable [rad].
  double max_refinement_move = rad_from_deg(10.0);
  // Static selection during the refinement: |residual| <= max(gate_sigmas * robust sigma of the
  // selected residuals, min_gate_mps).
  double gate_sigmas = 3.0;
  double min_gate_mps = 0.1;  // [m/s]
  double huber_sigmas = 1.5;  // Huber kernel width in robust sigmas
  int max_iterations = 30;
  double convergence = rad_from_deg(1e-5);  // stop when psi moves less than this [rad]

  // Ego-speed scale s (range_rate = -(s v_car + omega x t_V_R) . u(theta + psi)): estimated with
  // psi when true (a CAN or INS speed a few per cent off would otherwise move psi by up to a
  // degree), else fixed at 1. A scale outside [min_speed_scale, max_speed_scale] is not a speed
  // error but a wrong model (azimuth in degrees, a flipped range-rate sign): unreliable. The coarse
  // search tries scales over that range in steps of coarse_scale_step.
  bool estimate_speed_scale = true;
  double min_speed_scale = 0.8;
  double max_speed_scale = 1.25;
  double coarse_scale_step = 0.05;
  // Without the scale estimated, its nominal 1-sigma error; its effect on psi sets a floor under
  // the standard error [-].
  double speed_scale_sigma = 0.01;

  // Standard error: a block-clustered sandwich over time blocks of block_s (detections of one
  // target, the ego speed's errors are correlated over seconds), times the Student-t factor
  // t(0.975, blocks - 1) / 1.96 so that +-2 SE stays a 95 % interval with few blocks; never below
  // the least-squares error nor min_yaw_std.
  double block_s = 3.0;                      // [s]
  int min_blocks = 3;                        // fewer: insufficient data
  double min_yaw_std = rad_from_deg(0.001);  // [rad]

  // Per-window fits (the window_yaw series and the agreement check).
  double window_s = 10.0;       // [s]
  int min_window_points = 50;   // static detections a window needs to count
  int min_static_points = 100;  // fewer static detections: insufficient data

  // Checks of the fit (docs/methods.md "Checks"); a failed one makes the result unreliable.
  // Residual spread: the robust sigma of the static residuals must not exceed
  // max_residual_sigma_ratio x the radar's nominal range-rate noise, nor max_residual_sigma_mps.
  double nominal_range_rate_sigma_mps = 0.1;  // ARS408 / ESR class [m/s]
  double max_residual_sigma_ratio = 3.0;
  double max_residual_sigma_mps = 0.5;  // [m/s]
  // Static fraction: at least this share of the detections fits the static model.
  double min_static_fraction = 0.2;
  // Agreement between windows: the robust sigma of (window psi - psi) / window SE at most this,
  // with at least min_windows_for_agreement windows.
  double max_window_spread = 3.0;
  int min_windows_for_agreement = 3;
  // Displacement: static targets must reappear where the fitted motion moves them after
  // displacement_horizon_s (within displacement_gate_m + displacement_gate_fraction x range),
  // more often than where the opposite motion would (a flipped range-rate sign fits the cosine
  // at psi + 180 deg exactly; only the positions tell). Checked when at least
  // min_displacement_tests static detections have a later scan to be found in.
  double displacement_horizon_s = 0.5;       // [s]
  double displacement_gate_m = 1.0;          // [m]
  double displacement_gate_fraction = 0.01;  // of the range [-]
  int min_displacement_tests = 50;
  int max_displacement_tests = 20000;  // more static detections: every k-th is tested

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// The position method (radar_position_method.hpp): grouping, the triangle test, the pair estimates
// and their combination.
struct RadarPositionMethodOptions {
  // Straight stretches of the drive (core/segmentation), judged at the GNSS/INS records with the
  // curvature yaw rate / speed; both detections of a pair lie in one stretch (paper: "straight-line
  // segments ... of sufficient length").
  SegmentationOptions straight{.min_speed = 3.0,
                               .max_abs_curvature = 0.01,
                               .min_duration_s = 2.0,
                               .max_gap_s = 0.5,
                               .end_trim_s = 0.0};
  // A track id is reused by the radar for another target after a break: a gap longer than this
  // within one id, or a jump below, starts a new object [s].
  double max_track_gap_s = 0.5;
  // Jump: the range moves more than this beyond what the range rate explains [m], or the point
  // moves across the line of sight faster than max_relative_speed_mps.
  double max_range_jump_m = 1.5;
  double max_relative_speed_mps = 70.0;  // [m/s]
  int min_observations = 5;              // shorter tracks (clutter, most ghosts) are dropped
  // Pairs whose radar moved less than this between the two detections are dropped: the triangle
  // is too thin for the angle (its error grows like range noise / baseline) [m].
  double min_baseline_m = 5.0;
  // The car's largest turn between the two detections of a pair: without the lever arm the turn
  // moves the radar sideways by turn x lever arm, unmodelled [rad].
  double max_pair_turn = rad_from_deg(0.5);
  double max_pair_turn_with_lever_arm = rad_from_deg(5.0);  // [rad]
  // Nominal 1-sigma noise of the radar and the dead reckoning, for the triangle test's tolerance
  // and the pairs' weights (Conti ARS408-like).
  double range_sigma_m = 0.25;               // [m]
  double azimuth_sigma = rad_from_deg(0.3);  // [rad]
  double odometry_sigma_fraction = 0.01;     // of the baseline (speed scale) [-]
  // Triangle test: a pair closes when | |apparent displacement| - baseline | <= triangle_sigmas *
  // its predicted sigma; an object is static when at least min_static_fraction of its pairs close.
  double triangle_sigmas = 3.0;
  double min_static_fraction = 0.8;
  // Velocity consistency (paper): pairs with confidence c < min_confidence are dropped. Near 90 deg
  // off the direction of motion the Doppler says nothing about the speed; |cos| is floored there.
  double min_confidence = 0.5;
  double min_abs_cos = 0.2;
  // Pair estimates more than outlier_sigmas robust sigmas (of the normalised residuals) from the
  // weighted mean are dropped.
  double outlier_sigmas = 3.0;
  int min_static_objects = 5;      // fewer: insufficient data
  int min_pairs = 20;              // fewer: insufficient data
  int min_objects_for_spread = 5;  // fewer: the standard error from the pairs' spread alone

  // Association of detections into tracks (radar_association.hpp) for radars that report no track
  // ids (cluster lists): used when no detection has an id and associate_without_track_ids, or
  // always with always_associate (a tracking radar's ids are then ignored).
  bool associate_without_track_ids = true;
  bool always_associate = false;
  // A detection joins a track when its normalised distance from the track's constant-velocity
  // prediction is within this many sigmas [-].
  double association_gate_sigmas = 4.0;
  double association_window_s = 1.0;  // the prediction's line fits the track's last ... [s]
  // What the constant-velocity prediction misses (the radar's path is not straight), added in
  // quadrature to the predicted sigma [m].
  double association_model_sigma_m = 0.2;
  // A track's second detection: the target's own speed across the line of sight allowed beyond a
  // static target's apparent motion [m/s].
  double association_max_target_speed_mps = 2.0;
  // The range rate of consecutive detections of a track changes by no more than this beyond
  // what straight relative motion allows (radar_association.hpp) [m/s].
  double association_max_range_rate_jump_mps = 1.5;

  // Checks of the fit (docs/methods.md, position method, "Checks"); a failed one makes the result
  // unreliable with the reason:
  // the pairs' yaws scatter more than this many times their predicted sigma (robust sigma of the
  // normalised residuals, diagnostics.noise_vs_nominal; ~1.0 Conti-like, ~1.3 Delphi-like) [-];
  double max_noise_vs_nominal = 3.0;
  // fewer than this share of the objects with usable pairs pass the triangle test [-];
  double min_static_object_fraction = 0.1;
  // the range rates of the static objects' detections against the static model under the pair
  // yaws, slope sum(v_r v_r,static) / sum(v_r,static^2), below this: ~1 when right, ~-1 when the
  // range-rate sign is flipped [-];
  double min_range_rate_slope = 0.5;
  // the azimuths of the detections span (5th to 95th percentile) less than this: no radar sees
  // through a slit; radians read as degrees [rad]. Azimuths beyond +-pi (degrees read as
  // radians) always fail.
  double min_azimuth_span = rad_from_deg(2.0);
  // The GNSS/INS speed's scale error is estimated from the static objects (their apparent
  // displacements against the dead-reckoned baselines; radar_position_method.hpp) and the
  // baselines corrected by it; a scale further than this from 1 fails: no speed sensor is that far
  // off, the speed is in other units or broken [-].
  bool estimate_odometry_scale = true;
  double max_speed_scale_error = 0.1;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// How --method auto chooses (radar_calibration.cpp, docs/methods.md).
struct RadarAutoOptions {
  // The methods agree when |yaw_velocity - yaw_position| <= agreement_sigmas * sqrt(se_v^2 +
  // se_p^2)
  // + agreement_floor; then the one with the smaller standard error is reported.
  double agreement_sigmas = 3.0;
  double agreement_floor = rad_from_deg(0.1);  // model errors the standard errors miss [rad]
  // When they disagree (and both passed their own checks), the one with the smaller standard error
  // is reported; the position method only if at least this many static objects support it. The
  // paper's reason to prefer the position method, a biased Doppler, is mostly gone: the velocity
  // method fits the speed scale and checks its residuals (docs/methods.md).
  int min_position_objects = 10;
  // Methods further apart than this cannot both be near the truth, and neither is trusted: the
  // result is unreliable. Larger than the biases docs/methods.md tabulates for the Doppler at
  // their nominal sizes [rad].
  double max_disagreement = rad_from_deg(1.0);

  void Check() const;  // throws std::invalid_argument naming the offending field
};

struct RadarCalibrationOptions {
  RadarMethod method = RadarMethod::kAuto;
  // The radar's position on the car, t_V_R's x and y [m]. When given, the radar's velocity
  // includes yaw rate x lever arm and turns are kept up to max_yaw_rate_with_lever_arm; when not,
  // detections taken while |yaw rate| > max_yaw_rate are dropped.
  std::optional<Eigen::Vector2d> lever_arm_in_vehicle;
  double min_speed_mps = 3.0;                               // slower: dropped [m/s]
  double max_yaw_rate = rad_from_deg(0.5);                  // without lever arm [rad/s]
  double max_yaw_rate_with_lever_arm = rad_from_deg(30.0);  // with it [rad/s]
  double min_range_m = 1.0;                                 // closer detections dropped [m]
  // The yaw rate is the slope of the INS yaw over this window (radar_ego_motion.hpp) [s].
  double yaw_rate_window_s = 1.0;
  // Detections between two GNSS/INS records further apart than this are dropped and counted
  // (rejections["in_ins_gap"]): there is no motion to interpolate there [s].
  double max_ins_gap_s = 1.0;
  RadarVelocityMethodOptions velocity;
  RadarPositionMethodOptions position;
  RadarAutoOptions automatic;

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// `detections` with times on the INS clock (radar_to_ins_time_offset), `ins` with strictly
// increasing times. Detections outside the INS span, or in a gap of it, are dropped and counted
// (rejections["outside_ins_span"], ["in_ins_gap"]). Returns an ok result, insufficient_data with a
// reason, or unreliable with the failed checks (the estimate kept for inspection), never NaN
// angles; throws std::invalid_argument only on invalid options.
CalibrationResult calibrate_radar(std::span<const io::RadarDetection> detections,
                                  std::span<const io::InsRecord> ins,
                                  const RadarCalibrationOptions& options = {});

}  // namespace x2car::radar
