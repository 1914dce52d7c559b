#include "x2car/lidar/lidar_calibration.hpp"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/prior_slope.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/core/standard_error.hpp"
#include "x2car/core/track_alignment_report.hpp"

namespace x2car::lidar {
namespace {

constexpr const char* kSensor = "lidar";

// One sweep on its way through the pipeline.
struct SweepInFlight {
  std::size_t index = 0;
  io::PointCloud cloud;
  std::optional<std::string> read_error;    // set when skip_bad_sweeps caught an InputError
  std::exception_ptr error;                 // any other error while reading or fitting it
  std::optional<double> ground_travel_yaw;  // set on the sweeps whose ground is fitted [rad]
};

// What one pass over the sweeps produced, for the sweeps that could be read.
struct SweepPass {
  std::vector<OdometryStep> steps;               // one per readable sweep
  std::vector<std::optional<GroundFit>> ground;  // one per readable sweep; set on every k-th
  std::int64_t unreadable = 0;                   // sweeps skipped (skip_bad_sweeps)
  std::optional<std::string> first_read_error;   // the earliest skipped sweep's message
  // The car's travel axis in the LiDAR's xy plane [rad], once the track covered
  // travel_axis_distance_m; the ground was fitted across it (else across the LiDAR's x axis).
  std::optional<double> travel_yaw;
};

// Leaves out the sweeps that could not be read: the odometry went on from the next one.
void drop_unreadable(const std::vector<std::uint8_t>& unreadable, SweepPass& pass) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < unreadable.size(); ++i) {
    if (unreadable[i]) continue;
    if (kept != i) {  // a self-move would leave a fit's failure message empty
      pass.steps[kept] = std::move(pass.steps[i]);
      pass.ground[kept] = std::move(pass.ground[i]);
    }
    ++kept;
  }
  pass.steps.resize(kept);
  pass.ground.resize(kept);
}

bool registered(const OdometryStep& step) {
  return step.status == RegistrationStatus::kOk || step.status == RegistrationStatus::kFirstSweep;
}

// The axis the car travels along, in the LiDAR's xy plane, from the odometry's steps: their
// directions averaged as axes (doubled angles, so backing up counts alike), weighted by their
// length. The ground's sideways limit is measured across it (GroundOptions::travel_yaw).
class TravelAxis {
 public:
  // The step from `previous` to `step`, both registered, taken when faster than min_speed [m/s].
  void add(const OdometryStep& previous, const OdometryStep& step, double min_speed) {
    const Eigen::Vector3d moved =
        previous.world_from_lidar.linear().transpose() *
        (step.world_from_lidar.translation() - previous.world_from_lidar.translation());
    const double length = moved.head<2>().norm();
    const double dt = step.time - previous.time;
    if (!(dt > 0.0) || !(length > min_speed * dt)) return;
    doubled_cos_sum_ += (moved.x() * moved.x() - moved.y() * moved.y()) / length;
    doubled_sin_sum_ += 2.0 * moved.x() * moved.y() / length;
    distance_m_ += length;
  }
  double distance_m() const { return distance_m_; }
  // The axis' angle from the LiDAR's x axis in (-90, 90] deg [rad]; 0 before any step.
  double yaw() const { return 0.5 * std::atan2(doubled_sin_sum_, doubled_cos_sum_); }

 private:
  double doubled_cos_sum_ = 0.0;
  double doubled_sin_sum_ = 0.0;
  double distance_m_ = 0.0;
};

// Reads sweep `index`; with skip_bad_sweeps an InputError marks the sweep unreadable instead of
// ending the run.
void read_sweep_in_flight(const SweepSource& sweeps, const LidarCalibrationOptions& options,
                          SweepInFlight& sweep) {
  try {
    sweep.cloud = sweeps.read(sweep.index);
  } catch (const InputError& error) {
    if (!options.skip_bad_sweeps) throw;
    sweep.read_error = error.what();
  }
}

// The ground of sweep `index` with the sideways limit across `travel_yaw`; seeded per sweep so
// the result does not depend on the threads' order.
GroundFit fit_ground_across(const io::PointCloud& cloud, std::size_t index, double travel_yaw,
                            const LidarCalibrationOptions& options, GroundScratch& scratch) {
  GroundOptions ground = options.ground;
  ground.travel_yaw = travel_yaw;
  return fit_ground(cloud, ground, options.seed + index, scratch);
}

// The odometry stamps a pose at its sweep's time plus the deskew time (the middle of the points'
// own times); per-point times from another origin can put a pose at or before the previous one,
// which the odometry refuses. That is the input's fault: say which sweep.
OdometryStep register_in_order(LidarOdometry& odometry, const SweepInFlight& sweep,
                               const SweepSource& sweeps) {
  try {
    return odometry.register_sweep(sweep.cloud, sweeps.times[sweep.index]);
  } catch (const std::invalid_argument& error) {
    throw InputError(
        fmt::format("sweep {} (time {:.6f} s)", sweep.index, sweeps.times[sweep.index]), 0, "t",
        fmt::format("its points' times put its pose at or before the previous "
                    "sweep's; are the per-point times relative to the sweep's start? "
                    "({})",
                    error.what()));
  }
}

// The sweeps whose ground was fitted before the track gave the travel's axis, fitted again (read
// again) across the whole track's axis.
void refit_early_ground(const SweepSource& sweeps, const LidarCalibrationOptions& options,
                        const std::vector<std::size_t>& early, double travel_yaw,
                        tbb::enumerable_thread_specific<GroundScratch>& scratch, SweepPass& pass) {
  std::vector<std::exception_ptr> errors(early.size());
  tbb::parallel_for(std::size_t{0}, early.size(), [&](std::size_t k) {
    try {
      const std::size_t index = early[k];
      pass.ground[index] =
          fit_ground_across(sweeps.read(index), index, travel_yaw, options, scratch.local());
    } catch (...) {
      errors[k] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

SweepPass run_sweep_pass(const SweepSource& sweeps, const LidarCalibrationOptions& options) {
  const std::size_t count = sweeps.times.size();
  SweepPass pass;
  pass.steps.resize(count);
  pass.ground.resize(count);
  std::vector<std::uint8_t> unreadable(count, 0);
  LidarOdometry odometry(options.odometry);
  TravelAxis travel;
  std::optional<std::size_t> last_registered;
  std::vector<std::size_t> early_ground;  // ground sweeps before the travel's axis was known
  std::size_t next = 0;
  std::size_t done = 0;
  tbb::enumerable_thread_specific<GroundScratch> scratch;
  // No exception may leave a filter: a pipeline cancelled by one leaks the sweeps in flight. The
  // first error in sweep order stops the reading and is rethrown once the pipeline has drained.
  std::exception_ptr first_error;
  std::atomic<bool> stopping = false;
  std::vector<std::exception_ptr> ground_errors(count);
  // Enough sweeps in flight to keep every core reading and fitting while the odometry runs, few
  // enough that memory stays bounded.
  const std::size_t in_flight = 2 * std::max<std::size_t>(2, std::thread::hardware_concurrency());
  using Sweep = std::shared_ptr<SweepInFlight>;
  tbb::parallel_pipeline(
      in_flight,
      tbb::make_filter<void, Sweep>(tbb::filter_mode::serial_in_order,
                                    [&](tbb::flow_control& control) -> Sweep {
                                      if (next == count || stopping.load()) {
                                        control.stop();
                                        return nullptr;
                                      }
                                      auto sweep = std::make_shared<SweepInFlight>();
                                      sweep->index = next++;
                                      return sweep;
                                    }) &
          tbb::make_filter<Sweep, Sweep>(tbb::filter_mode::parallel,
                                         [&](Sweep sweep) {
                                           if (stopping.load()) return sweep;
                                           try {
                                             read_sweep_in_flight(sweeps, options, *sweep);
                                           } catch (...) {
                                             sweep->error = std::current_exception();
                                           }
                                           return sweep;
                                         }) &
          // The odometry, in order; it decides the axis the sweep's ground is fitted across.
          tbb::make_filter<Sweep, Sweep>(
              tbb::filter_mode::serial_in_order,
              [&](Sweep sweep) {
                if (first_error) return sweep;
                try {
                  if (sweep->error) std::rethrow_exception(sweep->error);
                  const std::size_t index = sweep->index;
                  if (sweep->read_error) {
                    unreadable[index] = 1;
                    if (pass.unreadable++ == 0) pass.first_read_error = sweep->read_error;
                  } else {
                    pass.steps[index] = register_in_order(odometry, *sweep, sweeps);
                    if (registered(pass.steps[index])) {
                      if (last_registered) {
                        travel.add(pass.steps[*last_registered], pass.steps[index],
                                   options.standing_speed);
                      }
                      last_registered = index;
                    }
                    if (index % static_cast<std::size_t>(options.ground_every) == 0) {
                      const bool known = travel.distance_m() >= options.travel_axis_distance_m;
                      if (!known) early_ground.push_back(index);
                      sweep->ground_travel_yaw = known ? travel.yaw() : 0.0;
                    }
                  }
                  if (options.progress) options.progress(++done, count);
                } catch (...) {
                  first_error = std::current_exception();
                  stopping = true;
                }
                return sweep;
              }) &
          tbb::make_filter<Sweep, void>(tbb::filter_mode::parallel, [&](const Sweep& sweep) {
            if (stopping.load() || !sweep->ground_travel_yaw) return;
            try {
              pass.ground[sweep->index] = fit_ground_across(
                  sweep->cloud, sweep->index, *sweep->ground_travel_yaw, options, scratch.local());
            } catch (...) {
              ground_errors[sweep->index] = std::current_exception();
            }
          }));
  if (first_error) std::rethrow_exception(first_error);
  for (const std::exception_ptr& error : ground_errors) {
    if (error) std::rethrow_exception(error);
  }
  if (travel.distance_m() >= options.travel_axis_distance_m) {
    pass.travel_yaw = travel.yaw();
    refit_early_ground(sweeps, options, early_ground, *pass.travel_yaw, scratch, pass);
  }
  drop_unreadable(unreadable, pass);
  return pass;
}

// The LiDAR's angular rate at each sweep from the odometry's poses [rad/s]: what the ground's turn
// gate tests.
std::vector<double> turn_rates_from(const std::vector<OdometryStep>& steps) {
  const std::size_t n = steps.size();
  std::vector<double> turn_rate(n, 0.0);
  if (n < 3) return turn_rate;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t before = i == 0 ? 0 : i - 1;
    const std::size_t after = std::min(n - 1, i + 1);
    const Eigen::Matrix3d& a = steps[before].world_from_lidar.linear();
    const Eigen::Matrix3d& b = steps[after].world_from_lidar.linear();
    turn_rate[i] =
        Eigen::AngleAxisd(a.transpose() * b).angle() / (steps[after].time - steps[before].time);
  }
  return turn_rate;
}

// The per-frame ground measurements that pass the gates.
struct GroundFrames {
  std::vector<double> time;
  std::vector<double> roll;
  std::vector<double> pitch;
  std::vector<double> height;
  std::vector<Eigen::Vector3d> normal;
  // The car's accelerations at each frame from the odometry [m/s^2], for the standard errors.
  std::vector<double> longitudinal_acceleration;
  std::vector<double> lateral_acceleration;  // positive turning left
  std::vector<double> speed;                 // [m/s], from the odometry
  std::int64_t fitted = 0;
  std::int64_t failed = 0;
  std::string first_failure;  // why the earliest failed fit failed (GroundFit::failure)
  std::int64_t turning = 0;
  std::int64_t unregistered = 0;
};

// The LiDAR's longitudinal and lateral acceleration at sweep i from the odometry, and its speed
// (the third component), by central
// differences over +-half_width sweeps: speed change over time, and speed times the signed turn
// rate about the LiDAR's z axis (near enough the car's for a mounting tilted a few degrees).
Eigen::Vector3d odometry_acceleration(const std::vector<OdometryStep>& steps, std::size_t i) {
  constexpr std::size_t kHalfWidth = 3;
  const std::size_t n = steps.size();
  const auto speed_at = [&](std::size_t j) {
    const std::size_t a = j == 0 ? 0 : j - 1, b = std::min(n - 1, j + 1);
    const double dt = steps[b].time - steps[a].time;
    return dt > 0.0
               ? (steps[b].world_from_lidar.translation() - steps[a].world_from_lidar.translation())
                         .norm() /
                     dt
               : 0.0;
  };
  const std::size_t before = i >= kHalfWidth ? i - kHalfWidth : 0;
  const std::size_t after = std::min(n - 1, i + kHalfWidth);
  const double dt = steps[after].time - steps[before].time;
  if (n < 3 || dt <= 0.0) return Eigen::Vector3d::Zero();
  const Eigen::AngleAxisd turn(steps[before].world_from_lidar.linear().transpose() *
                               steps[after].world_from_lidar.linear());
  const double yaw_rate = turn.angle() * turn.axis().z() / dt;
  return {(speed_at(after) - speed_at(before)) / dt, speed_at(i) * yaw_rate, speed_at(i)};
}

GroundFrames gate_ground_frames(const SweepPass& pass, const std::vector<double>& turn_rate,
                                const LidarCalibrationOptions& options) {
  GroundFrames frames;
  const std::size_t n = pass.steps.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!pass.ground[i]) continue;
    const GroundFit& fit = *pass.ground[i];
    if (!fit.plane) {
      if (frames.failed++ == 0) frames.first_failure = fit.failure;
      continue;
    }
    ++frames.fitted;
    const bool neighbours_registered = registered(pass.steps[i]) &&
                                       (i == 0 || registered(pass.steps[i - 1])) &&
                                       (i + 1 == n || registered(pass.steps[i + 1]));
    if (!neighbours_registered) {
      ++frames.unregistered;
      continue;
    }
    if (turn_rate[i] > options.max_ground_turn_rate) {
      ++frames.turning;
      continue;
    }
    const GroundPlane& plane = *fit.plane;
    frames.time.push_back(pass.steps[i].time);
    frames.roll.push_back(roll_from_ground(plane.normal_in_lidar));
    frames.pitch.push_back(pitch_from_ground(plane.normal_in_lidar));
    frames.height.push_back(plane.height_m);
    frames.normal.push_back(plane.normal_in_lidar);
    const Eigen::Vector3d acceleration = odometry_acceleration(pass.steps, i);
    frames.longitudinal_acceleration.push_back(acceleration.x());
    frames.lateral_acceleration.push_back(acceleration.y());
    frames.speed.push_back(acceleration.z());
  }
  return frames;
}

// Why the ground fits failed, for the reason: the first failure, and when most failed, where the
// road is looked for. A LiDAR mounted upside down, or tilted far down at the road ahead, has none
// of it there.
std::string describe_ground_failures(const GroundFrames& frames, const GroundOptions& ground) {
  if (frames.failed == 0) return "";
  std::string text = fmt::format("; the first failed fit: {}", frames.first_failure);
  if (2 * frames.failed >= frames.fitted + frames.failed) {
    text += fmt::format(
        " (the road is looked for {:g}-{:g} m below the LiDAR, as a plane within {:g} deg of its "
        "z axis: a LiDAR mounted upside down or tilted more than that is not calibrated by the "
        "ground)",
        ground.min_height_m, ground.max_height_m, deg_from_rad(ground.max_tilt));
  }
  return text;
}

// A robust estimate of one mounting quantity from per-frame values.
struct FrameEstimate {
  double value = 0.0;
  double standard_error = 0.0;
  std::int64_t used = 0;
  std::int64_t outliers = 0;
  // The pitch's fit of the body's lean (pitch_from_frames); empty for the other quantities.
  std::optional<OffsetWithSlope> lean_fit;
  double mean_longitudinal_acceleration = 0.0;  // [m/s^2], of the frames used for that fit
};

// Standard error of the mean of the used frames' residuals (core/standard_error.hpp): the moving
// blocks over time, Student-t corrected for their few degrees of freedom (frames close in time see
// the same stretch of road and share its errors, so their count overstates the information), never
// below the frames taken as independent.
double frame_standard_error(std::span<const double> times, std::span<const double> residuals,
                            const std::vector<bool>& used, double block_s) {
  std::vector<double> used_times;
  std::vector<double> used_residuals;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!used[i]) continue;
    used_times.push_back(times[i]);
    used_residuals.push_back(residuals[i]);
  }
  if (used_residuals.size() < 2) return 0.0;
  return series_standard_error(used_times, used_residuals, {.block_s = block_s}).combined;
}

// The median of the per-frame values (roll and height): it averages the body's lean when braking
// against speeding up and in left turns against right ones (the pitch fits its lean out instead,
// pitch_from_frames). Frames more than k robust sigmas from it
// are counted as outliers and left out of the standard error. The standard error is taken from the
// residuals less each frame's expected lean (`lean`, empty: none) about the median's: the median
// cancels the lean's swings, so they are no error of it; what it leaves is in `floor` (the
// ground's bias that no spread shows), added in quadrature.
FrameEstimate estimate_from_frames(std::span<const double> times, std::span<const double> values,
                                   std::span<const double> lean, double floor,
                                   const LidarCalibrationOptions& options) {
  // The median's standard error over the mean's, for normally distributed values: sqrt(pi / 2).
  constexpr double kMedianEfficiency = 1.2533141373155003;
  FrameEstimate estimate;
  estimate.value = median(values);
  std::vector<double> residuals(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) residuals[i] = values[i] - estimate.value;
  const std::vector<bool> used = mad_inlier_mask(residuals, options.ground_outliers);
  estimate.used = std::ranges::count(used, true);
  estimate.outliers = static_cast<std::int64_t>(values.size()) - estimate.used;
  if (!lean.empty()) {
    const double median_lean = median(lean);
    for (std::size_t i = 0; i < values.size(); ++i) residuals[i] -= lean[i] - median_lean;
  }
  estimate.standard_error = std::hypot(
      kMedianEfficiency * frame_standard_error(times, residuals, used, options.block_s), floor);
  return estimate;
}

// The odometry's poses with the LiDAR levelled by the ground's roll and pitch: a frame whose
// z axis is the car's, so its heading differs from the car's by the mounting yaw alone. The world
// is the first levelled frame, whose z is the car's up at the start.
SensorTrack levelled_track(const std::vector<OdometryStep>& steps, double roll, double pitch) {
  const Eigen::Matrix3d levelled_from_lidar = rotation_from_euler({roll, pitch, 0.0});
  const Eigen::Matrix3d level_world_from_world =
      levelled_from_lidar * steps.front().world_from_lidar.linear().transpose();
  SensorTrack track;
  for (const OdometryStep& step : steps) {
    track.time.push_back(step.time);
    track.position_enu.push_back(level_world_from_world * step.world_from_lidar.translation());
    track.world_from_sensor.push_back(level_world_from_world * step.world_from_lidar.linear() *
                                      levelled_from_lidar.transpose());
  }
  return track;
}

// The odometry's path on a map (the report): x and y of the levelled track [m].
void write_path_series(const SensorTrack& track, CalibrationResult& result) {
  Series x{"odometry_x", "m", track.time, {}};
  Series y{"odometry_y", "m", track.time, {}};
  for (const Eigen::Vector3d& position : track.position_enu) {
    x.value.push_back(position.x());
    y.value.push_back(position.y());
  }
  result.series.push_back(std::move(x));
  result.series.push_back(std::move(y));
}

// Roll, pitch and height from the ground frames (DESIGN §2): the typed estimate of the ground.
struct GroundEstimate {
  FrameEstimate roll;    // [rad]
  FrameEstimate pitch;   // [rad]
  FrameEstimate height;  // [m]
};

// Each frame's expected lean of the body (DESIGN §1 signs): speeding up lifts the nose (pitch
// < 0), a left turn lifts the left side (roll > 0), and a nose that dips lowers a LiDAR ahead of
// the point the body pitches about.
struct BodyLean {
  std::vector<double> roll, pitch, height;  // [rad], [rad], [m]
};

BodyLean body_lean_of(const GroundFrames& frames, const GroundBias& bias) {
  BodyLean lean;
  for (std::size_t i = 0; i < frames.time.size(); ++i) {
    const double pitch = -bias.pitch_per_acceleration * frames.longitudinal_acceleration[i];
    lean.pitch.push_back(pitch);
    lean.roll.push_back(bias.roll_per_lateral_acceleration * frames.lateral_acceleration[i]);
    lean.height.push_back(-bias.height_per_pitch_m * pitch);
  }
  return lean;
}

// What the median leaves of the body's lean: it cancels only when the drive's accelerations balance
// (braking against speeding up, left against right). The shift of the median when each frame's
// expected lean is taken out, |median(v) - median(v - lean)|, is what the lean moved it by; no
// spread of the frames shows it (a 25 s drive that speeds up all along: 0.8 deg of pitch). Added
// in quadrature to the floor.
double lean_floor(std::span<const double> values, std::span<const double> lean, double floor) {
  std::vector<double> levelled(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) levelled[i] = values[i] - lean[i];
  return std::hypot(floor, median(values) - median(levelled));
}

// The pitch at rest: each frame's pitch is the mounting's plus the body's lean, which follows the
// longitudinal acceleration (speeding up lifts the nose), v_i = pitch + gain * (-a_i). The gain is
// fitted with the passenger-car range as its prior (core/prior_slope.hpp): where the drive brakes
// and speeds up, the frames pin it down and the lean leaves the estimate; where it does not (a
// drive that speeds up all along), the prior's spread goes into the standard error. The median
// gate of estimate_from_frames picks the outliers.
FrameEstimate pitch_from_frames(const GroundFrames& frames,
                                const LidarCalibrationOptions& options) {
  const GroundBias& bias = options.ground_bias;
  std::vector<double> lean_regressor(frames.time.size());
  std::vector<double> residuals(frames.time.size());
  for (std::size_t i = 0; i < frames.time.size(); ++i) {
    lean_regressor[i] = -frames.longitudinal_acceleration[i];
    residuals[i] = frames.pitch[i] - bias.pitch_per_acceleration * lean_regressor[i];
  }
  const double centre = median(residuals);
  for (double& residual : residuals) residual -= centre;
  const std::vector<bool> used = mad_inlier_mask(residuals, options.ground_outliers);
  FrameEstimate estimate;
  estimate.used = std::ranges::count(used, true);
  estimate.outliers = static_cast<std::int64_t>(frames.time.size()) - estimate.used;
  if (estimate.used < 2) {  // too few frames to fit (the caller reports insufficient data)
    const BodyLean lean = body_lean_of(frames, bias);
    return estimate_from_frames(frames.time, frames.pitch, lean.pitch,
                                lean_floor(frames.pitch, lean.pitch, bias.pitch), options);
  }
  const OffsetWithSlope fit = offset_with_prior_slope(
      frames.time, frames.pitch, lean_regressor, used,
      {.mean = bias.pitch_per_acceleration, .standard_deviation = bias.pitch_per_acceleration_std},
      {.block_s = options.block_s}, bias.pitch);
  estimate.value = fit.offset;
  estimate.standard_error = fit.standard_error;
  estimate.lean_fit = fit;
  double sum_acceleration = 0.0;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i]) sum_acceleration += frames.longitudinal_acceleration[i];
  }
  estimate.mean_longitudinal_acceleration = sum_acceleration / static_cast<double>(estimate.used);
  return estimate;
}

GroundEstimate estimate_ground(const GroundFrames& frames, const LidarCalibrationOptions& options) {
  const GroundBias& bias = options.ground_bias;
  const BodyLean lean = body_lean_of(frames, bias);
  // The height's spread keeps the lean's swings: its lever arm is a guess (height_per_pitch_m).
  return {estimate_from_frames(frames.time, frames.roll, lean.roll,
                               lean_floor(frames.roll, lean.roll, bias.roll), options),
          pitch_from_frames(frames, options),
          estimate_from_frames(frames.time, frames.height, {},
                               lean_floor(frames.height, lean.height, bias.height_m), options)};
}

// The road under a LiDAR that stands still does not change. When the odometry has the car standing
// for most of the ground frames while their pitch or roll spreads (interquartile range) more than
// the limit, the odometry has lost the motion (a featureless stretch), and with it the
// accelerations that the pitch's lean is fitted against: the ground's numbers are one lean of
// several, not the mounting.
std::optional<std::string> check_ground_against_odometry(const GroundFrames& frames,
                                                         const LidarCalibrationOptions& options) {
  std::vector<double> pitch, roll;
  for (std::size_t i = 0; i < frames.time.size(); ++i) {
    if (frames.speed[i] >= options.standing_speed) continue;
    pitch.push_back(frames.pitch[i]);
    roll.push_back(frames.roll[i]);
  }
  if (static_cast<double>(pitch.size()) <= 0.5 * static_cast<double>(frames.time.size())) {
    return std::nullopt;
  }
  const auto spread = [](std::vector<double> values) {
    std::ranges::sort(values);
    const auto at = [&](double q) {
      return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
    };
    return at(0.75) - at(0.25);
  };
  const double pitch_spread = spread(pitch), roll_spread = spread(roll);
  const double worst = std::max(pitch_spread, roll_spread);
  if (worst <= options.max_standing_ground_spread) return std::nullopt;
  return fmt::format(
      "ground: the odometry has the LiDAR standing (below {:g} m/s) in {} of {} ground frames, "
      "but the road under it changes ({} interquartile range {:.2f} deg, more than {:.2f}): the "
      "odometry lost the motion, so the body's lean cannot be taken out of the ground's roll and "
      "pitch",
      options.standing_speed, pitch.size(), frames.time.size(),
      pitch_spread >= roll_spread ? "pitch" : "roll", deg_from_rad(worst),
      deg_from_rad(options.max_standing_ground_spread));
}

void write_ground_counts(const GroundFrames& frames, CalibrationResult& result) {
  result.support["ground_fits"] = frames.fitted;
  result.rejections["ground_failed"] = frames.failed;
  result.rejections["ground_turning"] = frames.turning;
  result.rejections["ground_unregistered"] = frames.unregistered;
}

void write_ground(const GroundEstimate& ground, const GroundFrames& frames,
                  CalibrationResult& result) {
  result.roll = ground.roll.value;
  result.roll_std = ground.roll.standard_error;
  result.pitch = ground.pitch.value;
  result.pitch_std = ground.pitch.standard_error;
  result.z = ground.height.value;
  result.z_std = ground.height.standard_error;
  result.support["ground_frames"] = static_cast<std::int64_t>(frames.time.size());
  // Frames left out of each quantity's standard error by median/MAD: three separate counts.
  result.rejections["ground_outlier_roll"] = ground.roll.outliers;
  result.rejections["ground_outlier_pitch"] = ground.pitch.outliers;
  result.rejections["ground_outlier_height"] = ground.height.outliers;
  if (ground.pitch.lean_fit) {
    result.diagnostics["pitch_per_acceleration_deg_per_mps2"] =
        deg_from_rad(ground.pitch.lean_fit->slope);
    result.diagnostics["pitch_per_acceleration_std_deg_per_mps2"] =
        deg_from_rad(ground.pitch.lean_fit->slope_std);
    result.diagnostics["ground_mean_longitudinal_acceleration_mps2"] =
        ground.pitch.mean_longitudinal_acceleration;
  }
}

void write_ground_series(const GroundFrames& frames, CalibrationResult& result) {
  result.series.push_back({"ground_roll", "rad", frames.time, frames.roll});
  result.series.push_back({"ground_pitch", "rad", frames.time, frames.pitch});
  result.series.push_back({"ground_height", "m", frames.time, frames.height});
  result.series.push_back(
      {"ground_longitudinal_acceleration", "m/s^2", frames.time, frames.longitudinal_acceleration});
  Series nx{"ground_normal_x", "", frames.time, {}};
  Series ny{"ground_normal_y", "", frames.time, {}};
  Series nz{"ground_normal_z", "", frames.time, {}};
  for (const Eigen::Vector3d& normal : frames.normal) {
    nx.value.push_back(normal.x());
    ny.value.push_back(normal.y());
    nz.value.push_back(normal.z());
  }
  result.series.push_back(std::move(nx));
  result.series.push_back(std::move(ny));
  result.series.push_back(std::move(nz));
}

// The motion's check of the ground. The track is levelled by the ground's roll and pitch, so the
// velocity runs in the levelled LiDAR's xy plane when they are right. Errors (d_roll, d_pitch) of
// theirs tilt that plane, and the car's travel, at the LiDAR's yaw psi in it, leaves it by
// e = -(cos psi d_pitch + sin psi d_roll): a LiDAR facing ahead or back checks its pitch, one
// facing sideways its roll (the other angle taken as the ground's). Adding back what the travel
// says is the motion's own estimate of that angle, checked against the ground's.
void write_motion_check(const TrackAlignment& alignment, const LidarCalibrationOptions& options,
                        CalibrationResult& result) {
  const SegmentAverage& elevation = *alignment.velocity_elevation_estimate;
  const double cos_yaw = std::cos(*result.yaw);
  const double sin_yaw = std::sin(*result.yaw);
  const bool facing_along = std::abs(cos_yaw) >= std::abs(sin_yaw);
  const char* angle = facing_along ? "pitch" : "roll";
  const double share = facing_along ? cos_yaw : sin_yaw;
  const double ground = facing_along ? *result.pitch : *result.roll;
  const double ground_std = facing_along ? *result.pitch_std : *result.roll_std;
  const double motion = ground + elevation.value / share;
  const double motion_std = elevation.standard_error / std::abs(share);
  result.diagnostics[fmt::format("motion_{}_deg", angle)] = deg_from_rad(motion);
  result.diagnostics[fmt::format("motion_{}_std_deg", angle)] = deg_from_rad(motion_std);
  if (options.disagreement(motion, motion_std, ground, ground_std)) {
    append_reason(result, fmt::format("the {} from the motion ({:.3f} deg) differs from the "
                                      "ground's ({:.3f} deg): check the odometry and the ground "
                                      "fits",
                                      angle, deg_from_rad(motion), deg_from_rad(ground)));
  }
}

// The yaw from the odometry's track: status and reason follow the alignment's outcome.
void write_yaw(const TrackAlignment& alignment, const LidarCalibrationOptions& options,
               CalibrationResult& result) {
  std::optional<YawChoice> choice;
  if (!alignment.insufficient_reason) {
    choice = choose_yaw(alignment, options.yaw_method, options.disagreement);
  }
  write_track_alignment(alignment, choice, options.keep_series, result);
  if (!choice) {
    result.status = CalibrationStatus::kInsufficientData;
    append_reason(result, "yaw: " + *alignment.insufficient_reason);
    return;
  }
  if (choice->disagreement) append_reason(result, *choice->disagreement);
  write_motion_check(alignment, options, result);
}

double path_length(const std::vector<OdometryStep>& steps) {
  double length = 0.0;
  for (std::size_t i = 1; i < steps.size(); ++i) {
    length +=
        (steps[i].world_from_lidar.translation() - steps[i - 1].world_from_lidar.translation())
            .norm();
  }
  return length;
}

// Registration failures by status and points skipped; returns the number of failed sweeps.
std::int64_t write_odometry_counts(const SweepPass& pass, CalibrationResult& result) {
  std::int64_t failed = 0;
  std::int64_t skipped_points = 0;
  for (const OdometryStep& step : pass.steps) {
    if (!registered(step)) {
      ++failed;
      ++result.rejections["registration_" + to_string(step.status)];
    }
    skipped_points += static_cast<std::int64_t>(step.invalid_points);
  }
  result.rejections["registration_failed"] = failed;
  result.rejections["non_finite_points"] = skipped_points;
  result.rejections["unreadable_sweep"] = pass.unreadable;
  result.diagnostics["odometry_path_length_m"] = path_length(pass.steps);
  if (pass.first_read_error) {
    append_reason(result, fmt::format("{} unreadable sweeps skipped, the first: {}",
                                      pass.unreadable, *pass.first_read_error));
  }
  return failed;
}

}  // namespace

void GroundBias::Check() const {
  const OptionsCheck check("GroundBias");
  check.non_negative("roll", roll);
  check.non_negative("pitch", pitch);
  check.non_negative("height_m", height_m);
  check.non_negative("pitch_per_acceleration", pitch_per_acceleration);
  check.positive("pitch_per_acceleration_std", pitch_per_acceleration_std);
  check.non_negative("roll_per_lateral_acceleration", roll_per_lateral_acceleration);
  check.non_negative("height_per_pitch_m", height_per_pitch_m);
}

void LidarCalibrationOptions::Check() const {
  odometry.Check();
  ground.Check();
  alignment.Check();
  ground_outliers.Check();
  ground_bias.Check();
  disagreement.Check();
  const OptionsCheck check("LidarCalibrationOptions");
  check.at_least("ground_every", ground_every, 1);
  check.positive("max_ground_turn_rate", max_ground_turn_rate);
  check.positive("block_s", block_s);
  check.positive("standing_speed", standing_speed);
  check.positive("max_standing_ground_spread", max_standing_ground_spread);
  check.non_negative("travel_axis_distance_m", travel_axis_distance_m);
  check.at_least("min_sweeps", static_cast<double>(min_sweeps), 3);
  check.at_least("min_ground_frames", static_cast<double>(min_ground_frames), 2);
  check.probability("max_failed_registration_share", max_failed_registration_share);
}

SweepSource sweep_source_from(const SweepFolder& folder) {
  SweepSource source;
  for (const SweepFile& sweep : folder.sweeps) source.times.push_back(sweep.time);
  // A copy: the source may outlive the folder it was made from.
  source.read = [folder = std::make_shared<const SweepFolder>(folder)](std::size_t index) {
    return read_sweep(*folder, folder->sweeps[index]);
  };
  return source;
}

CalibrationResult calibrate_lidar(const SweepSource& sweeps,
                                  const LidarCalibrationOptions& options) {
  options.Check();
  const auto started = std::chrono::steady_clock::now();
  std::optional<std::string> ground_unreliable;
  const auto finish = [&](CalibrationResult& result) {
    if (ground_unreliable) {
      // A failed check of the fit outranks too little data: the numbers are there, but wrong. It
      // comes first in the reason too: an odometry that lost the motion also explains the yaw's
      // counts of samples too slow.
      result.status = CalibrationStatus::kUnreliable;
      result.reason =
          *ground_unreliable + (result.reason.empty() ? std::string() : "; " + result.reason);
    }
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return result;
  };
  if (sweeps.times.size() < options.min_sweeps) {
    CalibrationResult result =
        insufficient_data(kSensor, fmt::format("only {} sweeps; need at least {} and {:g} s of "
                                               "straight driving for the yaw",
                                               sweeps.times.size(), options.min_sweeps,
                                               options.alignment.min_valid_duration_s));
    return finish(result);
  }
  const SweepPass pass = run_sweep_pass(sweeps, options);
  const std::size_t count = pass.steps.size();

  CalibrationResult result;
  result.sensor = kSensor;
  result.status = CalibrationStatus::kOk;
  result.support["sweeps"] = static_cast<std::int64_t>(count);
  const std::int64_t failed_registrations = write_odometry_counts(pass, result);
  if (pass.travel_yaw) result.diagnostics["ground_travel_yaw_deg"] = deg_from_rad(*pass.travel_yaw);
  if (count < options.min_sweeps) {
    result.status = CalibrationStatus::kInsufficientData;
    append_reason(result, fmt::format("only {} readable sweeps; need at least {}", count,
                                      options.min_sweeps));
    return finish(result);
  }

  const GroundFrames frames = gate_ground_frames(pass, turn_rates_from(pass.steps), options);
  write_ground_counts(frames, result);
  if (options.keep_series) write_ground_series(frames, result);
  if (frames.time.size() < options.min_ground_frames) {
    result.status = CalibrationStatus::kInsufficientData;
    append_reason(result,
                  fmt::format("only {} usable ground frames (of {} fitted; {} failed, {} while "
                              "turning, {} around failed registrations); need at least {}{}",
                              frames.time.size(), frames.fitted, frames.failed, frames.turning,
                              frames.unregistered, options.min_ground_frames,
                              describe_ground_failures(frames, options.ground)));
    return finish(result);
  }
  // Roll, pitch and height stand on their own: they are reported even when the yaw lacks data.
  const GroundEstimate ground = estimate_ground(frames, options);
  write_ground(ground, frames, result);
  ground_unreliable = check_ground_against_odometry(frames, options);

  const double failed_share =
      static_cast<double>(failed_registrations) / static_cast<double>(count);
  if (failed_share > options.max_failed_registration_share) {
    result.status = CalibrationStatus::kInsufficientData;
    append_reason(
        result,
        fmt::format("yaw: the odometry failed on {} of {} sweeps (more than {:g} %), so "
                    "its track cannot be trusted",
                    failed_registrations, count, 100.0 * options.max_failed_registration_share));
    return finish(result);
  }
  const SensorTrack track = levelled_track(pass.steps, *result.roll, *result.pitch);
  if (options.keep_series) write_path_series(track, result);
  const TrackAlignment alignment = align_track(track, options.alignment);
  write_yaw(alignment, options, result);
  return finish(result);
}

}  // namespace x2car::lidar
