// A spinning multi-beam LiDAR (DESIGN §4) in the world of world_scene.hpp.
//
// The head spins clockwise seen from above (as Velodyne, Ouster and Hesai heads do) at rate_hz;
// each sweep starts facing start_azimuth (default: backwards, so that the seam is behind the car)
// and fires columns every azimuth_step. All beams of a column fire at the column's time, each at
// its elevation and with its azimuth offset from the beam table. The sensor's pose for a column is
// the vehicle's pose at that exact time (states interpolated: position linear, attitude slerp)
// composed with vehicle_from_lidar, so a sweep taken while driving is distorted by the motion, as
// a real one is; each point is in the LiDAR frame at its own time, with t its time since the
// sweep's start.
//
// A return needs a surface within [min_range_m, max_range_m] and enough signal: reflectivity x
// cos(incidence) / range^2 >= 0.1 / range_10pct_m^2 (a 10 % target at normal incidence is seen to
// range_10pct_m). Returns are then dropped at random with dropout_probability, and get Gaussian
// range noise along the beam. Intensity = 255 x reflectivity x cos(incidence), clipped to 255.
// Draws come from a stream per sweep (Random::derive_seed(seed, sweep index)), so a sweep is the
// same whichever thread makes it. Not modelled: beam divergence and mixed pixels, multiple
// returns, the beams' origin offsets from the axis, the car's own body, rain and fog.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/io/point_cloud.hpp"
#include "x2car/sim/vehicle_state.hpp"
#include "x2car/sim/world_scene.hpp"

namespace x2car::sim {

struct LidarBeam {
  double elevation = 0.0;       // above the xy plane of the LiDAR frame [rad]
  double azimuth_offset = 0.0;  // added to the column's azimuth, counter-clockwise [rad]
};

// Beam tables, sorted by elevation from the lowest up (the ring number is the index):
//   32: OS1-32-like, 32 beams evenly from -22.5 to +22.5 deg, azimuth offsets repeating
//       +3.164, +1.055, -1.055, -3.164 deg;
//   64: HDL-64E-like, 32 beams from -24.33 to -8.83 deg every 0.5 deg and 32 from -8.33 to
//       +2.0 deg every 1/3 deg, azimuth offsets repeating -4.5, -1.5, +1.5, +4.5 deg;
//  128: Pandar128-like, 48 beams from -25 to -6.4 deg, 64 dense ones from -6 to +2 deg (1/8 deg
//       apart) and 16 from +2.8 to +15 deg, azimuth offsets repeating -3, -1, +1, +3 deg.
// Throws std::invalid_argument for any other count.
std::vector<LidarBeam> lidar_beam_table(int beams);

struct LidarOptions {
  int beams = 64;                           // 32, 64 or 128 (lidar_beam_table)
  double rate_hz = 10.0;                    // sweeps per second [Hz]
  double azimuth_step = rad_from_deg(0.2);  // between firing columns [rad]: 1800 per sweep
  double start_azimuth = kPi;               // where each sweep starts, in the LiDAR frame [rad]
  double range_noise_m = 0.02;              // Gaussian range noise, 1 sigma [m]
  double min_range_m = 0.5;                 // [m]
  double max_range_m = 120.0;               // [m]
  double range_10pct_m = 150.0;             // a 10 % target at normal incidence is seen to [m]
  double dropout_probability = 0.01;        // returns lost at random, [0, 1)

  int columns() const;  // firing columns per sweep: round(2 pi / azimuth_step)
  void Check() const;   // throws std::invalid_argument naming the offending field
};

struct LidarSweep {
  std::size_t index = 0;    // 0 for the first sweep of the log
  double start_time = 0.0;  // [s] on the log's clock
  io::PointCloud cloud;     // x y z in the LiDAR frame at each point's time, intensity, ring, t
  std::vector<std::uint32_t> object_ids;  // ground truth: what each point hit (not written)
};

// world_from_vehicle at `time` [s]: position linear and attitude slerped between the two states
// around it (clamped to the first and last). `states` must have strictly increasing times.
Eigen::Isometry3d world_from_vehicle_at(const VehicleStates& states, double time);

class LidarSimulator {
 public:
  // Keeps references to `scene` and `states`. Throws std::invalid_argument on bad options or
  // fewer than 2 states.
  LidarSimulator(const WorldScene& scene, const VehicleStates& states,
                 const Eigen::Isometry3d& vehicle_from_lidar, const LidarOptions& options,
                 std::uint64_t seed);
  LidarSimulator(const WorldScene&, VehicleStates&&, const Eigen::Isometry3d&, const LidarOptions&,
                 std::uint64_t) = delete;  // the states must outlive it

  // Whole sweeps within the states' time span.
  std::size_t sweep_count() const { return sweep_count_; }
  double sweep_start_time(std::size_t index) const;  // [s]
  const std::vector<LidarBeam>& beams() const { return beams_; }
  const LidarOptions& options() const { return options_; }

  // The sensor's pose at `time` [s]: world_from_vehicle_at(time) * vehicle_from_lidar.
  Eigen::Isometry3d world_from_lidar(double time) const;

  // Sweep `index` (< sweep_count()); thread-safe and deterministic.
  LidarSweep sweep(std::size_t index) const;

 private:
  const WorldScene& scene_;
  const VehicleStates& states_;
  Eigen::Isometry3d vehicle_from_lidar_;
  LidarOptions options_;
  std::uint64_t seed_;
  std::vector<LidarBeam> beams_;
  std::vector<Eigen::Vector2d> beam_cos_sin_elevation_, beam_cos_sin_offset_;
  std::size_t sweep_count_ = 0;
};

// Makes every sweep, in parallel (oneTBB), handing each to `sink` as soon as it is made: from
// worker threads, in no particular order, so `sink` must be thread-safe. At most one sweep per
// worker is in memory at a time.
void for_each_lidar_sweep(const LidarSimulator& lidar,
                          const std::function<void(LidarSweep&&)>& sink);

}  // namespace x2car::sim
