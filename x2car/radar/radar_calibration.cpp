#include "x2car/radar/radar_calibration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/radar/radar_auto.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_position_method.hpp"
#include "x2car/radar/radar_velocity_method.hpp"

namespace x2car::radar {
namespace {

struct GatedSamples {
  std::vector<RadarSample> samples;
  std::int64_t outside_ins_span = 0;
  std::int64_t in_ins_gap = 0;
  std::int64_t slow = 0;
  std::int64_t turning = 0;
  std::int64_t too_close = 0;
  double max_speed_mps = 0.0;
};

// Drops detections taken while the car is slow or (without a lever arm) turning, and those too
// close to the radar for a stable azimuth.
GatedSamples gate_samples(const RadarEgoMotion& motion, const RadarCalibrationOptions& options) {
  GatedSamples gated;
  gated.outside_ins_span = motion.counts.outside_ins_span;
  gated.in_ins_gap = motion.counts.in_ins_gap;
  const double max_yaw_rate =
      options.lever_arm_in_vehicle ? options.max_yaw_rate_with_lever_arm : options.max_yaw_rate;
  for (const RadarSample& sample : motion.samples) {
    gated.max_speed_mps = std::max(gated.max_speed_mps, std::abs(sample.car_speed_mps));
    if (std::abs(sample.car_speed_mps) < options.min_speed_mps) {
      ++gated.slow;
    } else if (std::abs(sample.yaw_rate) > max_yaw_rate) {
      ++gated.turning;
    } else if (sample.range < options.min_range_m) {
      ++gated.too_close;
    } else {
      gated.samples.push_back(sample);
    }
  }
  return gated;
}

// The gate's counts go into every result, whichever method made it.
void add_gate_rejections(CalibrationResult& result, const GatedSamples& gated) {
  result.rejections["outside_ins_span"] = gated.outside_ins_span;
  result.rejections["in_ins_gap"] = gated.in_ins_gap;
  result.rejections["slow"] = gated.slow;
  result.rejections["turning"] = gated.turning;
  result.rejections["too_close"] = gated.too_close;
}

}  // namespace

constexpr std::array<EnumName<RadarMethod>, 3> kRadarMethodNames{{
    {RadarMethod::kAuto, "auto"},
    {RadarMethod::kVelocity, "velocity"},
    {RadarMethod::kPosition, "position"},
}};

const char* to_string(RadarMethod method) { return enum_to_string(kRadarMethodNames, method); }

RadarMethod radar_method_from_string(const std::string& text) {
  return enum_from_string(kRadarMethodNames, text, "radar method");
}

std::vector<std::string> radar_method_names() { return enum_names(kRadarMethodNames); }

void RadarVelocityMethodOptions::Check() const {
  const OptionsCheck check("RadarVelocityMethodOptions");
  check.that(!nominal_yaw || std::isfinite(*nominal_yaw), "nominal_yaw", "must be finite");
  check.in_range("search_half_range", search_half_range, 0.0, kPi, Bounds::kOpenMax);
  check.in_range("search_step", search_step, 0.0, kPi / 4.0, Bounds::kOpenMin);
  check.positive("coarse_tolerance_mps", coarse_tolerance_mps);
  check.at_least("max_coarse_detections", max_coarse_detections, 1);
  check.positive("max_refinement_move", max_refinement_move);
  check.positive("gate_sigmas", gate_sigmas);
  check.positive("min_gate_mps", min_gate_mps);
  check.positive("huber_sigmas", huber_sigmas);
  check.at_least("max_iterations", max_iterations, 1);
  check.positive("convergence", convergence);
  check.positive("min_speed_scale", min_speed_scale);
  check.ordered("min_speed_scale", min_speed_scale, "max_speed_scale", max_speed_scale);
  check.that(min_speed_scale <= 1.0 && max_speed_scale >= 1.0, "min_speed_scale, max_speed_scale",
             "must contain 1");
  check.positive("coarse_scale_step", coarse_scale_step);
  check.non_negative("speed_scale_sigma", speed_scale_sigma);
  check.positive("block_s", block_s);
  check.at_least("min_blocks", min_blocks, 2);
  check.non_negative("min_yaw_std", min_yaw_std);
  check.positive("window_s", window_s);
  check.at_least("min_window_points", min_window_points, 3);
  check.at_least("min_static_points", min_static_points, 3);
  check.positive("nominal_range_rate_sigma_mps", nominal_range_rate_sigma_mps);
  check.positive("max_residual_sigma_ratio", max_residual_sigma_ratio);
  check.positive("max_residual_sigma_mps", max_residual_sigma_mps);
  check.probability("min_static_fraction", min_static_fraction);
  check.positive("max_window_spread", max_window_spread);
  check.at_least("min_windows_for_agreement", min_windows_for_agreement, 2);
  check.positive("displacement_horizon_s", displacement_horizon_s);
  check.positive("displacement_gate_m", displacement_gate_m);
  check.non_negative("displacement_gate_fraction", displacement_gate_fraction);
  check.at_least("min_displacement_tests", min_displacement_tests, 1);
  check.at_least("max_displacement_tests", max_displacement_tests, 1);
}

void RadarCalibrationOptions::Check() const {
  const OptionsCheck check("RadarCalibrationOptions");
  check.that(!lever_arm_in_vehicle || lever_arm_in_vehicle->allFinite(), "lever_arm_in_vehicle",
             "must be finite");
  check.positive("min_speed_mps", min_speed_mps);
  check.non_negative("max_yaw_rate", max_yaw_rate);
  check.non_negative("max_yaw_rate_with_lever_arm", max_yaw_rate_with_lever_arm);
  check.non_negative("min_range_m", min_range_m);
  check.positive("yaw_rate_window_s", yaw_rate_window_s);
  check.positive("max_ins_gap_s", max_ins_gap_s);
  velocity.Check();
  position.Check();
  automatic.Check();
}

void RadarPositionMethodOptions::Check() const {
  straight.Check();
  const OptionsCheck check("RadarPositionMethodOptions");
  check.positive("max_track_gap_s", max_track_gap_s);
  check.positive("max_range_jump_m", max_range_jump_m);
  check.non_negative("max_relative_speed_mps", max_relative_speed_mps);
  check.at_least("min_observations", min_observations, 2);
  check.positive("min_baseline_m", min_baseline_m);
  check.non_negative("max_pair_turn", max_pair_turn);
  check.non_negative("max_pair_turn_with_lever_arm", max_pair_turn_with_lever_arm);
  check.positive("range_sigma_m", range_sigma_m);
  check.positive("azimuth_sigma", azimuth_sigma);
  check.non_negative("odometry_sigma_fraction", odometry_sigma_fraction);
  check.positive("triangle_sigmas", triangle_sigmas);
  check.in_range("min_static_fraction", min_static_fraction, 0.0, 1.0, Bounds::kOpenMin);
  // A pair kept at confidence 0 would have weight 0: all such pairs leave no weighted mean.
  check.in_range("min_confidence", min_confidence, 0.0, 1.0, Bounds::kOpen);
  check.in_range("min_abs_cos", min_abs_cos, 0.0, 1.0, Bounds::kOpenMin);
  check.positive("outlier_sigmas", outlier_sigmas);
  check.at_least("min_static_objects", min_static_objects, 1);
  check.at_least("min_pairs", min_pairs, 2);
  check.at_least("min_objects_for_spread", min_objects_for_spread, 2);
  check.positive("association_gate_sigmas", association_gate_sigmas);
  check.positive("association_window_s", association_window_s);
  check.non_negative("association_model_sigma_m", association_model_sigma_m);
  check.non_negative("association_max_target_speed_mps", association_max_target_speed_mps);
  check.positive("association_max_range_rate_jump_mps", association_max_range_rate_jump_mps);
  check.positive("max_noise_vs_nominal", max_noise_vs_nominal);
  check.in_range("min_static_object_fraction", min_static_object_fraction, 0.0, 1.0);
  check.in_range("min_range_rate_slope", min_range_rate_slope, -1.0, 1.0);
  check.non_negative("min_azimuth_span", min_azimuth_span);
  check.positive("max_speed_scale_error", max_speed_scale_error);
}

void RadarAutoOptions::Check() const {
  const OptionsCheck check("RadarAutoOptions");
  check.positive("agreement_sigmas", agreement_sigmas);
  check.non_negative("agreement_floor", agreement_floor);
  check.at_least("min_position_objects", min_position_objects, 1);
  check.positive("max_disagreement", max_disagreement);
}

CalibrationResult calibrate_radar(std::span<const io::RadarDetection> detections,
                                  std::span<const io::InsRecord> ins,
                                  const RadarCalibrationOptions& options) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  if (ins.size() < 2) {
    CalibrationResult result = insufficient_data(
        "radar", fmt::format("need at least 2 GNSS/INS records, got {}", ins.size()));
    result.method = to_string(options.method);
    return result;
  }
  const RadarEgoMotion motion = radar_ego_motion(detections, ins, options.lever_arm_in_vehicle,
                                                 options.yaw_rate_window_s, options.max_ins_gap_s);
  const GatedSamples gated = gate_samples(motion, options);
  const auto by_velocity = [&] {
    return velocity_method_result(
        estimate_yaw_by_velocity(gated.samples, gated.max_speed_mps, options.velocity));
  };
  const auto by_position = [&] {
    if (gated.samples.empty()) {
      CalibrationResult result = insufficient_data(
          "radar", fmt::format("only 0 radar detections taken while the car moved at >= {:.1f} "
                               "m/s (fastest {:.1f} m/s)",
                               options.min_speed_mps, gated.max_speed_mps));
      result.method = "position";
      return result;
    }
    return position_method(gated.samples, motion.records, options.lever_arm_in_vehicle,
                           options.position);
  };
  CalibrationResult result;
  switch (options.method) {
    case RadarMethod::kVelocity:
      result = by_velocity();
      break;
    case RadarMethod::kPosition:
      result = by_position();
      break;
    case RadarMethod::kAuto: {
      // The two methods share only read-only inputs; running the position method beside the
      // velocity method keeps auto within the time of the slower one.
      std::future<CalibrationResult> position = std::async(std::launch::async, by_position);
      CalibrationResult velocity = by_velocity();
      result = choose_radar_method(std::move(velocity), position.get(), options.automatic);
      break;
    }
  }
  add_gate_rejections(result, gated);
  if (gated.outside_ins_span > 0 && !result.ok()) {
    result.reason +=
        fmt::format(" ({} detections outside the GNSS/INS time span)", gated.outside_ins_span);
  }
  if (gated.in_ins_gap > 0 && !result.ok()) {
    result.reason += fmt::format(
        " ({} detections between GNSS/INS records more than {:g} s apart, max_ins_gap_s)",
        gated.in_ins_gap, options.max_ins_gap_s);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace x2car::radar
