#include "x2car/radar/radar_calibration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <stdexcept>

#include "x2car/core/robust_stats.hpp"
#include "x2car/radar/radar_auto.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_position_method.hpp"
#include "x2car/radar/radar_velocity_method.hpp"

namespace x2car::radar {
namespace {

void require(bool condition, const char* field) {
  if (!condition) throw std::invalid_argument(fmt::format("radar calibration options: {}", field));
}

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

const char* to_string(RadarMethod method) {
  switch (method) {
    case RadarMethod::kAuto:
      return "auto";
    case RadarMethod::kVelocity:
      return "velocity";
    case RadarMethod::kPosition:
      return "position";
  }
  return "auto";
}

RadarMethod radar_method_from_string(const std::string& text) {
  for (const RadarMethod method :
       {RadarMethod::kAuto, RadarMethod::kVelocity, RadarMethod::kPosition}) {
    if (text == to_string(method)) return method;
  }
  throw std::invalid_argument(
      fmt::format("unknown radar method '{}' (expected auto, velocity or position)", text));
}

void RadarVelocityMethodOptions::Check() const {
  require(search_half_range >= 0.0 && search_half_range < kPi,
          "velocity.search_half_range must be in [0, pi)");
  require(search_step > 0.0, "velocity.search_step must be > 0");
  require(coarse_tolerance_mps > 0.0, "velocity.coarse_tolerance_mps must be > 0");
  require(gate_sigmas > 0.0, "velocity.gate_sigmas must be > 0");
  require(min_gate_mps > 0.0, "velocity.min_gate_mps must be > 0");
  require(huber_sigmas > 0.0, "velocity.huber_sigmas must be > 0");
  require(max_iterations >= 1, "velocity.max_iterations must be >= 1");
  require(convergence > 0.0, "velocity.convergence must be > 0");
  require(window_s > 0.0, "velocity.window_s must be > 0");
  require(min_window_points >= 3, "velocity.min_window_points must be >= 3");
  require(min_windows_for_spread >= 2, "velocity.min_windows_for_spread must be >= 2");
  require(min_static_points >= 3, "velocity.min_static_points must be >= 3");
}

void RadarCalibrationOptions::Check() const {
  require(!lever_arm_in_vehicle || lever_arm_in_vehicle->allFinite(),
          "lever_arm_in_vehicle must be finite");
  require(min_speed_mps > 0.0, "min_speed_mps must be > 0");
  require(max_yaw_rate >= 0.0, "max_yaw_rate must be >= 0");
  require(max_yaw_rate_with_lever_arm >= 0.0, "max_yaw_rate_with_lever_arm must be >= 0");
  require(min_range_m >= 0.0, "min_range_m must be >= 0");
  require(yaw_rate_window_s > 0.0, "yaw_rate_window_s must be > 0");
  require(max_ins_gap_s > 0.0, "max_ins_gap_s must be > 0");
  velocity.Check();
  position.Check();
  automatic.Check();
}

void RadarPositionMethodOptions::Check() const {
  straight.Check();
  require(max_track_gap_s > 0.0, "position.max_track_gap_s must be > 0");
  require(max_range_jump_m > 0.0, "position.max_range_jump_m must be > 0");
  require(max_relative_speed_mps >= 0.0, "position.max_relative_speed_mps must be >= 0");
  require(min_observations >= 2, "position.min_observations must be >= 2");
  require(min_baseline_m > 0.0, "position.min_baseline_m must be > 0");
  require(max_pair_turn >= 0.0 && max_pair_turn_with_lever_arm >= 0.0,
          "position.max_pair_turn* must be >= 0");
  require(range_sigma_m > 0.0, "position.range_sigma_m must be > 0");
  require(azimuth_sigma > 0.0, "position.azimuth_sigma must be > 0");
  require(odometry_sigma_fraction >= 0.0, "position.odometry_sigma_fraction must be >= 0");
  require(triangle_sigmas > 0.0, "position.triangle_sigmas must be > 0");
  require(min_static_fraction > 0.0 && min_static_fraction <= 1.0,
          "position.min_static_fraction must be in (0, 1]");
  // A pair kept at confidence 0 would have weight 0: all such pairs leave no weighted mean.
  require(min_confidence > 0.0 && min_confidence < 1.0,
          "position.min_confidence must be in (0, 1)");
  require(min_abs_cos > 0.0 && min_abs_cos <= 1.0, "position.min_abs_cos must be in (0, 1]");
  require(outlier_sigmas > 0.0, "position.outlier_sigmas must be > 0");
  require(min_static_objects >= 1, "position.min_static_objects must be >= 1");
  require(min_pairs >= 2, "position.min_pairs must be >= 2");
  require(min_objects_for_spread >= 2, "position.min_objects_for_spread must be >= 2");
}

void RadarAutoOptions::Check() const {
  require(agreement_sigmas > 0.0, "automatic.agreement_sigmas must be > 0");
  require(agreement_floor >= 0.0, "automatic.agreement_floor must be >= 0");
  require(min_position_objects >= 1, "automatic.min_position_objects must be >= 1");
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
