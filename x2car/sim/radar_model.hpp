// 2-D automotive radar model, ARS408-like by default: an object list per scan with persistent
// track ids, seen from the radar's pose on the moving car (DESIGN §4).
//
// Geometry at a scan time t (VehicleStates interpolated: position linear, rotation slerp,
// velocities linear):
//   world_from_radar = world_from_vehicle(t) * vehicle_from_radar
//   v_radar          = v_vehicle + R_W_V (omega_V x t_V_R)      exact rigid-body velocity [m/s]
//   p_in_radar       = radar_from_world * p_target
//   v_rel_in_radar   = R_R_W (v_target - v_radar)
// The radar is 2-D: it measures in its own x-y plane and ignores z (every target is taken to
// reflect at the radar's height, as a pole or a car body does for a radar with a narrow elevation
// beam):
//   x, y = p_in_radar.xy; range = hypot(x, y); azimuth = atan2(y, x), counter-clockwise positive
//   vx, vy = v_rel_in_radar.xy; range_rate = (x vx + y vy) / range, NEGATIVE when approaching
// so that a static target seen while driving straight at speed v with mounting yaw psi has
// range_rate = -v cos(azimuth + psi).
//
// Per scan (each scan draws from its own random stream, Random::derive_seed(seed, scan index)):
//  1. Field of view: range >= min_range_m and either |azimuth| <= near_max_azimuth within
//     near_max_range_m, or |azimuth| <= far_max_azimuth within far_max_range_m.
//  2. Detection probability (radar equation, range^-4): margin [dB] = rcs - 40 log10(range /
//     reference_range_m) - edge_loss_db (azimuth / near_max_azimuth)^2, Pd = max_detection_
//     probability / (1 + exp(-margin / detection_slope_db)).
//  3. Noise (Gaussian, 1 sigma): range, azimuth, range rate, each of vx and vy, RCS; x, y are
//     computed from the noisy range and azimuth. A measurement that falls outside the field of
//     view is not reported.
//  4. Tracks (reported when track_ids; a cluster list otherwise): a target keeps its id while seen;
//  missed up to max_coast_scans scans in a row it
//     keeps it silently, after that (or leaving the field of view) the track ends and its id is
//     free again (re-used: the lowest free id not released in the same scan). A track breaks with
//     track_break_probability per scan: the target is lost for [min_break_scans, max_break_scans]
//     scans and comes back with a new id. Ids run 0 .. track_id_count - 1; when all are taken, new
//     targets are not reported.
//  5. Ghosts: a reported target within ghost_max_range_m starts a double-bounce multipath ghost
//     (echo radar -> target -> car -> target -> radar) with ghost_birth_probability per scan: twice
//     the range, the same azimuth, twice the relative velocity and range rate, rcs - ghost_loss_db;
//     it ends with ghost_death_probability per scan or when its target is not reported.
//  6. Clutter: Poisson(clutter_rate) new false targets per scan at uniformly random points of the
//     near field of view, each living [1, clutter_max_lifetime_scans] scans at a fixed world
//     position; a share clutter_static_fraction of them stand still (they look like static
//     targets), the others move with a random horizontal velocity (random Doppler).
// Not modelled: occlusion, extended targets (several reflections of one object), merging of close
// targets, elevation, sensor latency, the radar's own object classification.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/sim/radar_scene.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

struct RadarOptions {
  double rate_hz = 1000.0 / 72.0;  // scans per second, 13.9 Hz (ARS408 cycle 72 ms) [Hz]

  // Field of view (ARS408: near scan +-60 deg to 70 m, far scan +-9 deg to 250 m).
  double min_range_m = 0.2;                      // [m]
  double near_max_range_m = 70.0;                // [m]
  double near_max_azimuth = rad_from_deg(60.0);  // [rad]
  double far_max_range_m = 250.0;                // [m]
  double far_max_azimuth = rad_from_deg(9.0);    // [rad]

  // Detection probability (step 2 above).
  double max_detection_probability = 0.95;  // of a strong target at short range, in (0, 1]
  double reference_range_m = 100.0;  // a 0 dBsm target on boresight is seen with half of it [m]
  double detection_slope_db = 3.0;   // width of the transition [dB], > 0
  double edge_loss_db = 6.0;         // antenna gain lost at the near azimuth limit [dB], >= 0

  // Measurement noise, 1 sigma.
  double range_sigma_m = 0.25;               // [m]
  double azimuth_sigma = rad_from_deg(0.3);  // [rad]
  double range_rate_sigma_mps = 0.1;         // [m/s]
  double velocity_sigma_mps = 0.1;           // each of vx, vy [m/s]
  double rcs_sigma_db = 1.0;                 // [dB]

  // Tracks (step 4 above).
  int track_id_count = 100;               // ids 0 .. count - 1 (Conti 100, Delphi 64), >= 1
  int max_coast_scans = 2;                // misses in a row a track survives
  double track_break_probability = 0.01;  // per track and scan
  int min_break_scans = 2;                // a broken track's target is lost this many scans...
  int max_break_scans = 6;                // ... to this many
  // Whether the radar reports its track ids (an object list). false: a cluster list, as many
  // real exports are: every detection has io::kNoTrackId and new_track false (the writers leave
  // the id field empty). The bookkeeping above still runs (it decides coasting and breaks); only
  // the ids are not reported. The truth file (radar_truth.csv) keeps no id either.
  bool track_ids = true;

  // Ghosts (step 5 above).
  double ghost_birth_probability = 0.01;  // per reported target within ghost_max_range_m and scan
  double ghost_death_probability = 0.2;   // per ghost and scan
  double ghost_max_range_m = 40.0;        // [m]
  double ghost_loss_db = 10.0;            // [dB]

  // Clutter (step 6 above).
  double clutter_rate = 1.0;             // new false targets per scan (Poisson mean), >= 0
  int clutter_max_lifetime_scans = 3;    // >= 1
  double clutter_static_fraction = 0.5;  // share of false targets that stand still, [0, 1]
  double clutter_max_speed_mps = 15.0;   // of the moving ones [m/s]

  // Continental ARS408-21: the defaults above.
  static RadarOptions conti_ars408();
  // Delphi ESR-like: 20 Hz, +-45 deg to 60 m and +-10 deg to 174 m, 64 track ids, range sigma
  // 0.3 m, azimuth sigma 0.4 deg, range rate sigma 0.12 m/s. Use it with the Delphi layout, whose
  // ids end at 63.
  static RadarOptions delphi_esr();

  void Check() const;  // throws std::invalid_argument naming the offending field
};

// Speed over ground [m/s] above which a detection's source counts as moving.
constexpr double kRadarMovingSpeedMps = 0.1;

enum class RadarSource {
  kTarget,   // a scene object (reflector or mover)
  kGhost,    // a multipath ghost of a scene object
  kClutter,  // a false target at a point where there is no object
};

struct SimulatedRadarDetection {
  // What the radar reports: time [s] on the drive's clock, track id, new_track, range, azimuth,
  // range rate, x, y, vx, vy (has_velocity), rcs.
  io::RadarDetection measurement;
  // Ground truth:
  io::RadarDetection truth;  // the same without noise (a ghost's apparent values)
  RadarSource source = RadarSource::kTarget;
  int object_id = -1;  // the scene object (a ghost's: its target's); -1 for clutter
  bool is_moving =
      false;  // the source's (for a ghost: its target's) ENU speed > kRadarMovingSpeedMps
};

struct RadarScan {
  double time = 0.0;                                // [s] on the drive's clock
  std::vector<SimulatedRadarDetection> detections;  // in ascending track id
};

// The radar's pose and velocity at a time inside the states' span.
struct RadarKinematics {
  Eigen::Isometry3d world_from_radar = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();  // of the radar's origin [m/s]
};

// Throws std::out_of_range outside [states.front().time, states.back().time].
RadarKinematics radar_kinematics_at(const VehicleStates& states,
                                    const Eigen::Isometry3d& vehicle_from_radar, double time);

// Scans at t = t0 + k / rate_hz for k = 0, 1, ... while t <= the last state's time (t0 = the first
// state's time), one entry per scan even when it has no detections. Same arguments -> identical
// scans. Throws std::invalid_argument on bad options, a bad scene (RadarScene::Check), or states
// that are fewer than 2 or do not strictly increase in time.
std::vector<RadarScan> simulate_radar(const VehicleStates& states,
                                      const Eigen::Isometry3d& vehicle_from_radar,
                                      const RadarScene& scene, const RadarOptions& options,
                                      std::uint64_t seed);

// The measurements of all scans in order, for the writers (io/radar_csv.hpp).
std::vector<io::RadarDetection> radar_measurements(std::span<const RadarScan> scans);

}  // namespace x2car::sim
