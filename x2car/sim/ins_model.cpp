#include "x2car/sim/ins_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "x2car/core/options_check.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

// A first-order Gauss-Markov process sampled at irregular steps; exact discretisation of
// db/dt = -b / tau + white noise with stationary standard deviation sigma.
class GaussMarkov {
 public:
  GaussMarkov(double sigma, double tau, Random& random)
      : sigma_(sigma), tau_(tau), value_(random.normal(0.0, sigma)) {}

  double value() const { return value_; }

  void step(double dt, Random& random) {
    const double phi = std::exp(-dt / tau_);
    value_ = phi * value_ + random.normal(0.0, sigma_ * std::sqrt(1.0 - phi * phi));
  }

 private:
  double sigma_;
  double tau_;
  double value_;
};

// The slowly varying device errors carried from sample to sample.
struct CorrelatedErrors {
  GaussMarkov east, north, up;  // position [m]
  GaussMarkov heading;          // heading bias [rad]

  CorrelatedErrors(const InsOptions& o, Random& random)
      : east(o.position_markov_sigma_horizontal, o.position_markov_tau, random),
        north(o.position_markov_sigma_horizontal, o.position_markov_tau, random),
        up(o.position_markov_sigma_vertical, o.position_markov_tau, random),
        heading(o.heading_bias_sigma, o.heading_bias_tau, random) {}

  void step(double dt, Random& random) {
    east.step(dt, random);
    north.step(dt, random);
    up.step(dt, random);
    heading.step(dt, random);
  }
};

std::size_t sampling_stride(const VehicleStates& truth, double rate_hz) {
  if (truth.size() < 2) return 1;
  const double span = truth.back().time - truth.front().time;
  if (!(span > 0.0)) throw std::invalid_argument("simulate_ins: truth times do not increase");
  const double truth_rate = static_cast<double>(truth.size() - 1) / span;  // [Hz]
  return static_cast<std::size_t>(std::max(1.0, std::round(truth_rate / rate_hz)));
}

// Adds one sample's errors in a fixed draw order: position, velocity, heading, roll, pitch.
void add_errors(const InsOptions& o, const CorrelatedErrors& correlated, Random& random,
                InsSample& sample) {
  const double h = o.position_white_sigma_horizontal;
  sample.position_enu +=
      Eigen::Vector3d(correlated.east.value(), correlated.north.value(), correlated.up.value());
  sample.position_enu.x() += random.normal(0.0, h);
  sample.position_enu.y() += random.normal(0.0, h);
  sample.position_enu.z() += random.normal(0.0, o.position_white_sigma_vertical);
  sample.velocity_enu *= o.velocity_scale;
  sample.velocity_enu.x() += random.normal(0.0, o.velocity_sigma_horizontal);
  sample.velocity_enu.y() += random.normal(0.0, o.velocity_sigma_horizontal);
  sample.velocity_enu.z() += random.normal(0.0, o.velocity_sigma_vertical);
  const double heading_error = correlated.heading.value() + random.normal(0.0, o.heading_sigma);
  sample.attitude.yaw = wrap_angle(sample.attitude.yaw + heading_error);
  sample.attitude.roll = wrap_angle(sample.attitude.roll + random.normal(0.0, o.roll_pitch_sigma));
  sample.attitude.pitch += random.normal(0.0, o.roll_pitch_sigma);
}

}  // namespace

InsOptions InsOptions::rtk() { return InsOptions{}; }

InsOptions InsOptions::sps() {
  InsOptions o;
  o.position_white_sigma_horizontal = 0.1;
  o.position_white_sigma_vertical = 0.15;
  o.position_markov_sigma_horizontal = 1.0;
  o.position_markov_sigma_vertical = 1.5;
  o.position_markov_tau = 10.0;
  o.velocity_sigma_horizontal = 0.1;
  o.velocity_sigma_vertical = 0.15;
  o.status = kStatusSinglePoint;
  return o;
}

void InsOptions::Check() const {
  const OptionsCheck check("InsOptions");
  check.positive("rate_hz", rate_hz);
  check.positive("position_markov_tau", position_markov_tau);
  check.positive("heading_bias_tau", heading_bias_tau);
  check.non_negative("position_white_sigma_horizontal", position_white_sigma_horizontal);
  check.non_negative("position_white_sigma_vertical", position_white_sigma_vertical);
  check.non_negative("position_markov_sigma_horizontal", position_markov_sigma_horizontal);
  check.non_negative("position_markov_sigma_vertical", position_markov_sigma_vertical);
  check.non_negative("velocity_sigma_horizontal", velocity_sigma_horizontal);
  check.non_negative("velocity_sigma_vertical", velocity_sigma_vertical);
  check.in_range("velocity_scale", velocity_scale, 0.5, 1.5);
  check.non_negative("heading_sigma", heading_sigma);
  check.non_negative("heading_bias_sigma", heading_bias_sigma);
  check.non_negative("roll_pitch_sigma", roll_pitch_sigma);
}

InsSample true_ins_sample(const VehicleState& state, const Eigen::Isometry3d& vehicle_from_ins) {
  const Eigen::Vector3d& lever_arm = vehicle_from_ins.translation();  // t_V_I [m]
  const Eigen::Matrix3d world_from_vehicle = state.world_from_vehicle.linear();
  InsSample sample;
  sample.time = state.time;
  sample.position_enu = state.world_from_vehicle * lever_arm;
  sample.velocity_enu =
      state.velocity_enu + world_from_vehicle * state.angular_velocity_vehicle.cross(lever_arm);
  sample.attitude = euler_from_rotation(world_from_vehicle * vehicle_from_ins.linear());
  return sample;
}

std::vector<InsSample> simulate_ins(const VehicleStates& truth,
                                    const Eigen::Isometry3d& vehicle_from_ins,
                                    const InsOptions& options, std::uint64_t seed) {
  options.Check();
  const std::size_t stride = sampling_stride(truth, options.rate_hz);
  Random random(seed);
  CorrelatedErrors correlated(options, random);
  std::vector<InsSample> samples;
  samples.reserve(truth.size() / stride + 1);
  for (std::size_t i = 0; i < truth.size(); i += stride) {
    if (i > 0) {
      const double dt = truth[i].time - truth[i - stride].time;  // [s]
      if (!(dt > 0.0)) throw std::invalid_argument("simulate_ins: truth times do not increase");
      correlated.step(dt, random);
    }
    InsSample sample = true_ins_sample(truth[i], vehicle_from_ins);
    add_errors(options, correlated, random, sample);
    sample.status = options.status;
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace x2car::sim
