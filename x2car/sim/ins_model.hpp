// GNSS/INS device model: samples the car's true motion at the device's lever arm and mounting
// rotation, and adds the errors of a real receiver-plus-IMU solution.
//
// Truth at the device (DESIGN §1; t = t_V_I the lever arm, R_V_I the mounting rotation):
//   position  p_W_I = world_from_vehicle * t
//   attitude  R_W_I = R_W_V * R_V_I          (reported as ZYX roll, pitch, yaw in ENU)
//   velocity  v_W_I = v_W_V + R_W_V (omega_V x t)
// so on a level straight the reported yaw minus the track heading is the mounting yaw.
//
// Errors, drawn per sample in a fixed order from one seeded stream:
//   position  white noise per axis + a first-order Gauss-Markov error per axis,
//             b_k+1 = phi b_k + sigma sqrt(1 - phi^2) w_k,  phi = exp(-dt / tau),  w ~ N(0, 1),
//             started from its stationary distribution N(0, sigma^2);
//   velocity  white noise per axis (not tied to the position error);
//   heading   white noise + a Gauss-Markov bias (as above, its own sigma and tau);
//   roll, pitch  white noise;
//   velocity scale  the reported velocity is velocity_scale times the true one (before its white
//             noise), as a speed taken from the wheels (CAN) is off by the tyres' rolling radius;
//             the position, and so the speed derived from it, stays true.
// Not modelled: outages, RTK fix changes, IMU lever-arm errors, latency.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/sim/vehicle_state.hpp"

namespace x2car::sim {

// NMEA GGA fix quality, the status the simulated device reports.
constexpr int kStatusSinglePoint = 1;
constexpr int kStatusRtkFixed = 4;

struct InsOptions {
  double rate_hz = 100.0;  // output rate [Hz]

  // Position error per axis (east and north share the horizontal values) [m]. The defaults are an
  // RTK-fixed solution: about 2 cm horizontal, 3 cm vertical, white.
  double position_white_sigma_horizontal = 0.02;  // [m]
  double position_white_sigma_vertical = 0.03;    // [m]
  double position_markov_sigma_horizontal = 0.0;  // stationary sigma of the correlated part [m]
  double position_markov_sigma_vertical = 0.0;    // [m]
  double position_markov_tau = 10.0;              // correlation time of the correlated part [s]

  double velocity_sigma_horizontal = 0.02;  // white, per axis [m/s]
  double velocity_sigma_vertical = 0.02;    // white [m/s]
  // Scale error of the reported velocity (all three axes): 1.02 reports 2 % too fast, as a CAN
  // wheel speed with worn tyres might. The position is not scaled. In [0.5, 1.5] [-].
  double velocity_scale = 1.0;

  double heading_sigma = rad_from_deg(0.05);       // white [rad]
  double heading_bias_sigma = rad_from_deg(0.02);  // Gauss-Markov bias, stationary sigma [rad]
  double heading_bias_tau = 300.0;                 // bias correlation time [s]
  double roll_pitch_sigma = rad_from_deg(0.02);    // white, each of roll and pitch [rad]

  int status = kStatusRtkFixed;  // reported in every sample (NMEA GGA fix quality)

  // RTK fixed: the defaults above.
  static InsOptions rtk();
  // Single point positioning: per axis a Gauss-Markov error of 1 m horizontal, 1.5 m vertical
  // (tau 10 s: atmosphere and multipath drift over seconds, not sample to sample) plus 0.1 m /
  // 0.15 m white noise; velocity 0.1 m/s horizontal, 0.15 m/s vertical. The attitude comes from
  // the IMU and keeps the RTK values. Status 1.
  static InsOptions sps();

  // Throws std::invalid_argument on a non-positive rate or correlation time or a negative sigma.
  void Check() const;
};

// One output sample; the record type the INS writers take (time [s], ENU position [m] and
// velocity [m/s] of the device, world_from_ins as ZYX roll, pitch, yaw_enu [rad], status).
using InsSample = io::InsRecord;

// Samples the device along `truth` (strictly increasing times, normally 100 Hz). The device
// reports at the truth's own times, every k-th state with k = max(1, round(truth_rate / rate_hz))
// where truth_rate = (n - 1) / (t_last - t_first): the rate is met exactly when the truth's rate
// is a multiple of it, and the device never reports faster than the truth is sampled. Same
// arguments -> identical samples. Throws std::invalid_argument on bad options or times that do
// not increase.
std::vector<InsSample> simulate_ins(const VehicleStates& truth,
                                    const Eigen::Isometry3d& vehicle_from_ins,
                                    const InsOptions& options, std::uint64_t seed);

// The error-free sample of the device at one true state (the formulas above).
InsSample true_ins_sample(const VehicleState& state, const Eigen::Isometry3d& vehicle_from_ins);

}  // namespace x2car::sim
