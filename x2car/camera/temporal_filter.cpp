#include "x2car/camera/temporal_filter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/core/standard_error.hpp"

namespace x2car::camera {

void TemporalFilterOptions::Check() const {
  const OptionsCheck check("TemporalFilterOptions");
  check.at_least("window_frames", window_frames, 2);
  check.positive("max_window_std", max_window_std);
  check.at_least("steadiness_block_frames", steadiness_block_frames, 1);
  check.at_most("steadiness_block_frames", steadiness_block_frames, window_frames / 2.0);
  check.positive("max_gap_s", max_gap_s);
  check.non_negative("min_speed_mps", min_speed_mps);
  check.positive("max_yaw_rate", max_yaw_rate);
  check.positive("max_acceleration_mps2", max_acceleration_mps2);
  check.positive("max_window_yaw_rate", max_window_yaw_rate);
  check.positive("image_motion_camera_height_m", image_motion_camera_height_m);
  check.non_negative("image_motion_significance", image_motion_significance);
  check.non_negative("weight_floor", weight_floor);
  check.positive("block_s", block_s);
  check.non_negative("standard_error_floor", standard_error_floor);
  check.at_least("min_road_plane_frames", min_road_plane_frames, 2);
  check.positive("road_plane_clip", road_plane_clip);
}

namespace {

constexpr std::array<EnumName<FrameVerdict>, 7> kFrameVerdictNames{{
    {FrameVerdict::kBuffered, "buffered"},
    {FrameVerdict::kWindowPassed, "window_passed"},
    {FrameVerdict::kNoEstimate, "no_estimate"},
    {FrameVerdict::kSlow, "slow"},
    {FrameVerdict::kTurning, "turning"},
    {FrameVerdict::kAccelerating, "accelerating"},
    {FrameVerdict::kReversing, "reversing"},
}};

double EulerAngles::*const kAngles[] = {&EulerAngles::roll, &EulerAngles::pitch, &EulerAngles::yaw};

double largest(const EulerAngles& angles) {
  return std::max({angles.roll, angles.pitch, angles.yaw});
}

// The least-squares line of `values` over `times`: its slope (0 without two distinct times), and
// the slope's standard error from the residuals (infinite with fewer than three samples).
struct LineFit {
  double slope = 0.0;
  double slope_error = std::numeric_limits<double>::infinity();
};

LineFit fit_line(std::span<const double> times, std::span<const double> values) {
  LineFit fit;
  const double mean_time = weighted_mean(times);
  const double mean_value = weighted_mean(values);
  double covariance = 0.0;
  double variance = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    covariance += (times[i] - mean_time) * (values[i] - mean_value);
    variance += (times[i] - mean_time) * (times[i] - mean_time);
  }
  if (!(variance > 0.0)) return fit;
  fit.slope = covariance / variance;
  if (times.size() < 3) return fit;
  double residual_squares = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double residual = values[i] - mean_value - fit.slope * (times[i] - mean_time);
    residual_squares += residual * residual;
  }
  fit.slope_error =
      std::sqrt(residual_squares / (static_cast<double>(times.size()) - 2.0) / variance);
  return fit;
}

}  // namespace

const char* to_string(FrameVerdict verdict) { return enum_to_string(kFrameVerdictNames, verdict); }

std::optional<FrameVerdict> motion_gate(const std::optional<VehicleMotion>& motion,
                                        const TemporalFilterOptions& options) {
  if (!motion) return std::nullopt;
  if (!(motion->speed_mps >= options.min_speed_mps)) return FrameVerdict::kSlow;
  if (motion->reversing) return FrameVerdict::kReversing;
  if (!(std::abs(motion->yaw_rate) <= options.max_yaw_rate)) return FrameVerdict::kTurning;
  if (!(std::abs(motion->acceleration_mps2) <= options.max_acceleration_mps2)) {
    return FrameVerdict::kAccelerating;
  }
  return std::nullopt;
}

ImageMotionJudgement judge_image_motion(const std::vector<double>& times,
                                        const std::vector<ImageMotion>& motions,
                                        const TemporalFilterOptions& options) {
  if (times.size() != motions.size()) {
    reject_argument("judge_image_motion: {} times for {} motions", times.size(), motions.size());
  }
  ImageMotionJudgement judgement;
  std::vector<double> kept_times;
  std::vector<double> yaw_rates;
  std::vector<double> speeds;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]) || !std::isfinite(motions[i].yaw_rate) ||
        !std::isfinite(motions[i].speed_over_height)) {
      continue;
    }
    kept_times.push_back(times[i]);
    yaw_rates.push_back(motions[i].yaw_rate);
    speeds.push_back(motions[i].speed_over_height);
  }
  if (kept_times.empty()) return judgement;
  // Pairs whose tracks locked onto a passing car are left out, as from the angles' means: beyond
  // road_plane_clip MADs of the yaw rates, or of the speeds about their straight line.
  const OutlierRejectionOptions clip{.k = options.road_plane_clip};
  const double first_slope = fit_line(kept_times, speeds).slope;
  std::vector<double> residuals(speeds.size());
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    residuals[i] = speeds[i] - first_slope * kept_times[i];
  }
  const std::vector<bool> yaw_inliers = mad_inlier_mask(yaw_rates, clip);
  const std::vector<bool> speed_inliers = mad_inlier_mask(residuals, clip);
  std::vector<double> inlier_times;
  std::vector<double> inlier_yaw_rates;
  std::vector<double> inlier_speeds;
  for (std::size_t i = 0; i < kept_times.size(); ++i) {
    if (yaw_inliers[i]) inlier_yaw_rates.push_back(yaw_rates[i]);
    if (speed_inliers[i]) {
      inlier_times.push_back(kept_times[i]);
      inlier_speeds.push_back(speeds[i]);
    }
  }
  // Each reading with its standard error: a window is refused only on evidence (below).
  double yaw_rate_error = std::numeric_limits<double>::infinity();
  if (!inlier_yaw_rates.empty()) judgement.yaw_rate = weighted_mean(inlier_yaw_rates);
  if (inlier_yaw_rates.size() >= 2) {
    yaw_rate_error = standard_deviation(inlier_yaw_rates) /
                     std::sqrt(static_cast<double>(inlier_yaw_rates.size()));
  }
  double acceleration_error = std::numeric_limits<double>::infinity();
  if (inlier_speeds.size() >= 2) {
    const LineFit fit = fit_line(inlier_times, inlier_speeds);
    judgement.acceleration_mps2 = fit.slope * options.image_motion_camera_height_m;
    acceleration_error = fit.slope_error * options.image_motion_camera_height_m;
  }
  judgement.yaw_rate_error = yaw_rate_error;
  judgement.acceleration_error_mps2 = acceleration_error;
  const double evidence = options.image_motion_significance;
  const auto beyond = [evidence](double value, double error, double limit) {
    return std::abs(value) > limit && std::abs(value) > evidence * error;
  };
  if (beyond(judgement.yaw_rate, yaw_rate_error, options.max_window_yaw_rate)) {
    judgement.refused = FrameVerdict::kTurning;
  } else if (beyond(judgement.acceleration_mps2, acceleration_error,
                    options.max_acceleration_mps2)) {
    judgement.refused = FrameVerdict::kAccelerating;
  }
  return judgement;
}

TemporalFilter::TemporalFilter(TemporalFilterOptions options) : options_(std::move(options)) {
  options_.Check();
  window_.reserve(static_cast<std::size_t>(options_.window_frames));
}

void TemporalFilter::end_stretch() {
  window_.clear();
  stretch_ = 0;
}

// Mean of each angle over the full window, and the std (n - 1) of its blocks' means (of its frames'
// angles with blocks of one frame); differences are taken from the first frame's angles on the
// circle, so the seam at +-pi cannot split a window.
bool TemporalFilter::window_passes(EulerAngles& mean, EulerAngles& std) const {
  const auto block = static_cast<std::size_t>(options_.steadiness_block_frames);
  const std::size_t blocks = window_.size() / block;
  const std::size_t first = window_.size() - blocks * block;  // the oldest frames left over
  const double n = static_cast<double>(window_.size());
  for (double EulerAngles::*angle : kAngles) {
    const double reference = window_.front().angles.*angle;
    double sum = 0.0;
    for (const Buffered& frame : window_) sum += angle_difference(frame.angles.*angle, reference);
    const double offset_mean = sum / n;
    mean.*angle = wrap_angle(reference + offset_mean);
    double sum_squares = 0.0;
    for (std::size_t start = first; start < window_.size(); start += block) {
      double block_sum = 0.0;
      for (std::size_t i = start; i < start + block; ++i) {
        block_sum += angle_difference(window_[i].angles.*angle, reference);
      }
      const double deviation = block_sum / static_cast<double>(block) - offset_mean;
      sum_squares += deviation * deviation;
    }
    std.*angle = std::sqrt(sum_squares / (static_cast<double>(blocks) - 1.0));
  }
  return largest(std) < options_.max_window_std;
}

// The window's roll and pitch from its frames' road-plane angles, when enough of them have them:
// their clipped means, and the means' standard errors as the window's spreads.
void TemporalFilter::take_road_plane_angles(FilterWindow& window) const {
  std::vector<double> rolls;
  std::vector<double> pitches;
  rolls.reserve(window_.size());
  pitches.reserve(window_.size());
  const EulerAngles reference = window.mean;
  for (const Buffered& frame : window_) {
    if (!frame.road_plane) continue;
    rolls.push_back(angle_difference(frame.road_plane->roll, reference.roll));
    pitches.push_back(angle_difference(frame.road_plane->pitch, reference.pitch));
  }
  const auto enough = static_cast<std::size_t>(options_.min_road_plane_frames);
  if (rolls.size() < enough) return;
  const OutlierRejectionOptions clip{.k = options_.road_plane_clip};
  const std::vector<bool> roll_inliers = mad_inlier_mask(rolls, clip);
  const std::vector<bool> pitch_inliers = mad_inlier_mask(pitches, clip);
  std::vector<double> kept_rolls;
  std::vector<double> kept_pitches;
  for (std::size_t i = 0; i < rolls.size(); ++i) {
    if (roll_inliers[i] && pitch_inliers[i]) {
      kept_rolls.push_back(rolls[i]);
      kept_pitches.push_back(pitches[i]);
    }
  }
  const std::size_t kept = kept_rolls.size();
  if (kept < enough) return;
  // The mean, and its standard error: the std over the square root of half the count, as
  // consecutive frame pairs share a frame.
  const auto mean_and_error = [](const std::vector<double>& values) {
    const double half = 0.5 * static_cast<double>(values.size());
    return std::pair{weighted_mean(values), standard_deviation(values) / std::sqrt(half)};
  };
  const auto [roll, roll_error] = mean_and_error(kept_rolls);
  const auto [pitch, pitch_error] = mean_and_error(kept_pitches);
  window.mean.roll = wrap_angle(reference.roll + roll);
  window.std.roll = roll_error;
  window.mean.pitch = wrap_angle(reference.pitch + pitch);
  window.std.pitch = pitch_error;
  window.road_plane_frames = kept;
}

std::optional<FrameVerdict> TemporalFilter::image_motion_gate(bool& known) const {
  known = std::all_of(window_.begin(), window_.end(),
                      [](const Buffered& frame) { return frame.has_vehicle_motion; });
  // Every frame passed the VehicleMotion gate; frames without one leave the images to tell.
  if (known) return std::nullopt;
  std::vector<double> times;
  std::vector<ImageMotion> motions;
  for (const Buffered& frame : window_) {
    if (!frame.road_plane || !frame.road_plane->motion) continue;
    const ImageMotion& motion = *frame.road_plane->motion;
    if (!std::isfinite(motion.yaw_rate) || !std::isfinite(motion.speed_over_height)) continue;
    times.push_back(frame.time - window_.front().time);
    motions.push_back(motion);
  }
  if (times.size() < static_cast<std::size_t>(options_.min_road_plane_frames)) return std::nullopt;
  known = true;
  return judge_image_motion(times, motions, options_).refused;
}

FrameVerdict TemporalFilter::add(double time_s, const std::optional<EulerAngles>& angles,
                                 const std::optional<VehicleMotion>& motion,
                                 std::optional<RoadPlaneAngles> road_plane) {
  if (!std::isfinite(time_s) || (last_time_ && time_s <= *last_time_)) {
    reject_argument(
        "TemporalFilter::add: frame time {} s is not finite or not after the "
        "previous frame's",
        time_s);
  }
  last_time_ = time_s;
  const std::size_t frame = frames_++;
  std::optional<FrameVerdict> rejected = motion_gate(motion, options_);
  if (!rejected && (!angles || !std::isfinite(angles->roll) || !std::isfinite(angles->pitch) ||
                    !std::isfinite(angles->yaw))) {
    // A hole, or the stretch's end (options); a gap too long ends it below, at the next estimate.
    if (!options_.unusable_frame_ends_stretch) return FrameVerdict::kNoEstimate;
    rejected = FrameVerdict::kNoEstimate;
  }
  if (rejected) {
    end_stretch();
    return *rejected;
  }
  const FrameVerdict verdict = FrameVerdict::kBuffered;
  if (last_usable_time_ && time_s - *last_usable_time_ > options_.max_gap_s) end_stretch();
  last_usable_time_ = time_s;
  ++usable_frames_;
  longest_stretch_ = std::max(longest_stretch_, ++stretch_);
  if (window_.size() == static_cast<std::size_t>(options_.window_frames)) {
    window_.erase(window_.begin());
  }
  if (road_plane && (!std::isfinite(road_plane->roll) || !std::isfinite(road_plane->pitch))) {
    road_plane.reset();
  }
  window_.push_back({frame, time_s, *angles, motion.has_value(), road_plane});
  if (window_.size() < static_cast<std::size_t>(options_.window_frames)) return verdict;

  FilterWindow passed;
  if (!window_passes(passed.mean, passed.std)) {
    if (!steadiest_failed_ || largest(passed.std) < largest(*steadiest_failed_)) {
      steadiest_failed_ = passed.std;
    }
    return verdict;
  }
  if (const std::optional<FrameVerdict> refused = image_motion_gate(passed.motion_known)) {
    ++(*refused == FrameVerdict::kTurning ? refused_turning_ : refused_accelerating_);
    return verdict;
  }
  passed.vehicle_motion_known =
      std::all_of(window_.begin(), window_.end(),
                  [](const Buffered& frame) { return frame.has_vehicle_motion; });
  passed.first_frame = window_.front().frame;
  passed.last_frame = window_.back().frame;
  passed.start_time = window_.front().time;
  passed.end_time = window_.back().time;
  take_road_plane_angles(passed);
  windows_.push_back(passed);
  window_.clear();  // the next window starts after this one: windows share no frames
  return FrameVerdict::kWindowPassed;
}

void TemporalFilter::refuse_standing_windows(const std::vector<bool>& stood) {
  if (stood.size() != windows_.size()) {
    throw std::invalid_argument(
        fmt::format("TemporalFilter::refuse_standing_windows: {} flags for {} windows",
                    stood.size(), windows_.size()));
  }
  std::vector<FilterWindow> kept;
  kept.reserve(windows_.size());
  for (std::size_t k = 0; k < windows_.size(); ++k) {
    if (stood[k]) {
      ++refused_standing_;
    } else {
      kept.push_back(windows_[k]);
    }
  }
  windows_ = std::move(kept);
}

void TemporalFilter::gate_windows_by_image_motion(
    const std::vector<std::optional<ImageMotionJudgement>>& judgements) {
  if (judgements.size() != windows_.size()) {
    reject_argument("TemporalFilter::gate_windows_by_image_motion: {} judgements for {} windows",
                    judgements.size(), windows_.size());
  }
  std::vector<FilterWindow> kept;
  kept.reserve(windows_.size());
  for (std::size_t k = 0; k < windows_.size(); ++k) {
    const std::optional<ImageMotionJudgement>& judgement = judgements[k];
    if (judgement && judgement->refused) {
      ++(*judgement->refused == FrameVerdict::kTurning ? refused_turning_ : refused_accelerating_);
      continue;
    }
    kept.push_back(windows_[k]);
    if (judgement) kept.back().motion_known = true;
  }
  windows_ = std::move(kept);
}

FilterEstimate TemporalFilter::current() const {
  FilterEstimate estimate;
  estimate.windows = windows_.size();
  estimate.windows_refused_turning = refused_turning_;
  estimate.windows_refused_accelerating = refused_accelerating_;
  estimate.windows_refused_standing = refused_standing_;
  const auto need = static_cast<std::size_t>(options_.window_frames);
  if (windows_.empty()) {
    if (longest_stretch_ < need) {
      estimate.reason =
          usable_frames_ < need
              ? fmt::format("only {} frames in stable stretches; need {}", usable_frames_, need)
              : fmt::format(
                    "only {} frames in stable stretches, at most {} in a row; need {} in "
                    "a row",
                    usable_frames_, longest_stretch_, need);
    } else if (refused_standing_ > 0) {
      estimate.reason = fmt::format(
          "the car stood through {} steady window{} of {} frames, all there were: their images "
          "did not move, and a car standing still is steady without driving straight",
          refused_standing_, refused_standing_ == 1 ? "" : "s", need);
      if (refused_turning_ + refused_accelerating_ > 0) {
        estimate.reason += fmt::format(
            " (the images' motion refused {} more for turning and {} for speeding up or braking)",
            refused_turning_, refused_accelerating_);
      }
    } else if (refused_turning_ + refused_accelerating_ > 0) {
      estimate.reason = fmt::format(
          "no steady window of {} frames was driven straight at a steady speed: the images' "
          "motion refused {} for turning (mean yaw rate above {:.2g} deg/s) and {} for "
          "speeding up or braking (above {:.2g} m/s^2 at a camera height of {:.2g} m); --ins "
          "gives the car's motion frame by frame",
          need, refused_turning_, deg_from_rad(options_.max_window_yaw_rate), refused_accelerating_,
          options_.max_acceleration_mps2, options_.image_motion_camera_height_m);
    } else {
      const EulerAngles std = steadiest_failed_.value_or(EulerAngles{});
      estimate.reason = fmt::format(
          "no window of {} frames was steady: the steadiest had std roll {:.3f}, pitch {:.3f}, "
          "yaw {:.3f} deg; need below {:.3f} deg",
          need, deg_from_rad(std.roll), deg_from_rad(std.pitch), deg_from_rad(std.yaw),
          deg_from_rad(options_.max_window_std));
    }
    return estimate;
  }
  estimate.ok = true;
  std::vector<double> times;
  std::vector<double> values;
  times.reserve(windows_.size());
  values.reserve(windows_.size());
  for (const FilterWindow& window : windows_) {
    estimate.frames_in_windows += window.last_frame - window.first_frame + 1;
    if (window.motion_known) ++estimate.motion_known_windows;
    if (window.vehicle_motion_known) ++estimate.vehicle_motion_windows;
    if (window.road_plane_frames > 0) {
      ++estimate.road_plane_windows;
      estimate.road_plane_frames += window.road_plane_frames;
    }
    times.push_back(0.5 * (window.start_time + window.end_time));
  }
  for (double EulerAngles::*angle : kAngles) {
    // The weighted mean, as offsets from the first window's on the circle.
    const double reference = windows_.front().mean.*angle;
    double weighted = 0.0;
    double weight_sum = 0.0;
    double weight_without_vehicle_motion = 0.0;
    values.clear();
    for (const FilterWindow& window : windows_) {
      const double spread = window.std.*angle;
      const double weight =
          1.0 / (spread * spread + options_.weight_floor * options_.weight_floor + 1e-30);
      const double offset = angle_difference(window.mean.*angle, reference);
      weighted += weight * offset;
      weight_sum += weight;
      if (!window.vehicle_motion_known) weight_without_vehicle_motion += weight;
      values.push_back(offset);
    }
    estimate.angles.*angle = wrap_angle(reference + weighted / weight_sum);
    if (angle == &EulerAngles::pitch) {
      estimate.pitch_weight_without_vehicle_motion = weight_without_vehicle_motion / weight_sum;
    }
    const double floor = options_.standard_error_floor.*angle;
    estimate.standard_error.*angle =
        windows_.size() >= 2
            ? series_standard_error(times, values, MovingBlockOptions{.block_s = options_.block_s},
                                    floor)
                  .combined
            : std::hypot(windows_.front().std.*angle, floor);
  }
  return estimate;
}

}  // namespace x2car::camera
