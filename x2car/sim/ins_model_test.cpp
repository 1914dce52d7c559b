// Tests of the GNSS/INS device model and of the seeded random draws it uses.
#include "x2car/sim/ins_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/sim/random.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::sim {
namespace {

using testing::straight_drive;
using x2car::testing::AngleNearDeg;

// ---- constructed truth -------------------------------------------------------------------------

// Where the straight drives start: away from the origin, so that positions are not trivially 0.
const Eigen::Vector3d kStart(5, -7, 30);

// Level circle of `radius` [m] driven left at `speed` [m/s]: position, heading, velocity and the
// yaw rate omega = speed / radius about the vehicle's z axis.
VehicleState circle_state(double time, double radius, double speed) {
  const double omega = speed / radius;  // [rad/s]
  const double heading = omega * time;
  VehicleState s;
  s.time = time;
  s.world_from_vehicle = make_transform(
      EulerAngles{0, 0, heading},
      Eigen::Vector3d(radius * std::sin(heading), radius * (1 - std::cos(heading)), 0));
  s.velocity_enu = speed * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  s.angular_velocity_vehicle = {0, 0, omega};
  s.speed = speed;
  s.yaw_rate = omega;
  s.path_curvature = 1.0 / radius;
  s.heading_enu = wrap_angle(heading);
  return s;
}

InsOptions noise_free() {
  InsOptions o;
  o.position_white_sigma_horizontal = o.position_white_sigma_vertical = 0.0;
  o.velocity_sigma_horizontal = o.velocity_sigma_vertical = 0.0;
  o.heading_sigma = o.heading_bias_sigma = o.roll_pitch_sigma = 0.0;
  return o;
}

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

double standard_deviation(const std::vector<double>& v) {
  const double m = mean(v);
  double sum = 0.0;
  for (const double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / static_cast<double>(v.size() - 1));
}

// Errors of the reported positions against the true device positions, per axis.
std::vector<std::vector<double>> position_errors(const std::vector<InsSample>& samples,
                                                 const VehicleStates& truth,
                                                 const Eigen::Isometry3d& vehicle_from_ins,
                                                 std::size_t stride = 1) {
  std::vector<std::vector<double>> errors(3);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d e =
        samples[i].position_enu - true_ins_sample(truth[i * stride], vehicle_from_ins).position_enu;
    for (int axis = 0; axis < 3; ++axis) errors[axis].push_back(e[axis]);
  }
  return errors;
}

const Eigen::Isometry3d kVehicleFromIns =
    make_transform(EulerAngles{rad_from_deg(0.8), rad_from_deg(-1.2), rad_from_deg(2.0)},
                   Eigen::Vector3d(0.4, -0.3, 1.6));

// ---- mounting geometry -------------------------------------------------------------------------

TEST(InsModel, YawMinusTrackHeadingIsTheMountingYawOnAStraight) {
  const double heading = rad_from_deg(30.0);
  const VehicleStates truth = straight_drive(60.0, 12.0, heading, 100.0, kStart);
  const InsOptions options = InsOptions::rtk();
  const std::vector<InsSample> samples = simulate_ins(truth, kVehicleFromIns, options, 7);
  std::vector<double> offsets, rolls, pitches;
  for (const InsSample& s : samples) {
    offsets.push_back(angle_difference(s.attitude.yaw, heading));
    rolls.push_back(s.attitude.roll);
    pitches.push_back(s.attitude.pitch);
  }
  const double n = static_cast<double>(samples.size());
  // White noise averages down as sigma / sqrt(n); the bias (tau 300 s) barely moves in 60 s:
  // allow it 4 sigma.
  const double yaw_tolerance =
      3 * options.heading_sigma / std::sqrt(n) + 4 * options.heading_bias_sigma;
  const double tilt_tolerance = 3 * options.roll_pitch_sigma / std::sqrt(n);
  EXPECT_THAT(mean(offsets), AngleNearDeg(rad_from_deg(2.0), deg_from_rad(yaw_tolerance)));
  EXPECT_THAT(mean(rolls), AngleNearDeg(rad_from_deg(0.8), deg_from_rad(tilt_tolerance)));
  EXPECT_THAT(mean(pitches), AngleNearDeg(rad_from_deg(-1.2), deg_from_rad(tilt_tolerance)));
  // and the white part has the configured spread
  EXPECT_NEAR(standard_deviation(rolls) / options.roll_pitch_sigma, 1.0, 0.1);
}

TEST(InsModel, SignCheckDeviceYawedLeftReportsPositiveOffset) {
  const VehicleStates truth = straight_drive(1.0, 10.0, rad_from_deg(-170.0), 100.0, kStart);
  const Eigen::Isometry3d yawed_left = make_transform(EulerAngles{0, 0, rad_from_deg(2.0)}, {});
  for (const InsSample& s : simulate_ins(truth, yawed_left, noise_free(), 1)) {
    EXPECT_THAT(angle_difference(s.attitude.yaw, rad_from_deg(-170.0)),
                AngleNearDeg(rad_from_deg(2.0), 1e-9));
  }
}

TEST(InsModel, PositionNoiseMatchesTheConfiguredSigma) {
  const VehicleStates truth = straight_drive(60.0, 12.0, 1.0, 100.0, kStart);
  const InsOptions options = InsOptions::rtk();
  const auto errors =
      position_errors(simulate_ins(truth, kVehicleFromIns, options, 11), truth, kVehicleFromIns);
  const std::vector<double> sigmas{options.position_white_sigma_horizontal,
                                   options.position_white_sigma_horizontal,
                                   options.position_white_sigma_vertical};
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(standard_deviation(errors[axis]) / sigmas[axis], 1.0, 0.1) << "axis " << axis;
    EXPECT_NEAR(mean(errors[axis]), 0.0, 4 * sigmas[axis] / std::sqrt(6001.0)) << "axis " << axis;
  }
}

TEST(InsModel, SpsPositionErrorHasItsSigmaAndIsTimeCorrelated) {
  // Three hours at 10 Hz: ~1000 correlation times, so the sample std is within a few percent.
  const VehicleStates truth = straight_drive(3 * 3600.0, 12.0, 1.0, 10.0, kStart);
  InsOptions options = InsOptions::sps();
  options.rate_hz = 10.0;
  const auto errors =
      position_errors(simulate_ins(truth, kVehicleFromIns, options, 5), truth, kVehicleFromIns);
  const double horizontal =
      std::hypot(options.position_markov_sigma_horizontal, options.position_white_sigma_horizontal);
  const double vertical =
      std::hypot(options.position_markov_sigma_vertical, options.position_white_sigma_vertical);
  EXPECT_NEAR(standard_deviation(errors[0]) / horizontal, 1.0, 0.1);
  EXPECT_NEAR(standard_deviation(errors[1]) / horizontal, 1.0, 0.1);
  EXPECT_NEAR(standard_deviation(errors[2]) / vertical, 1.0, 0.1);
  // Successive errors 0.1 s apart are strongly correlated: their difference is far smaller than
  // the error itself (white part sqrt(2) * 0.1 m, Gauss-Markov step ~0.14 m).
  std::vector<double> steps;
  for (std::size_t i = 1; i < errors[0].size(); ++i)
    steps.push_back(errors[0][i] - errors[0][i - 1]);
  EXPECT_LT(standard_deviation(steps), 0.3 * horizontal);
}

TEST(InsModel, HeadingBiasDriftsSlowly) {
  const VehicleStates truth = straight_drive(4 * 3600.0, 12.0, 0.3, 10.0, kStart);
  InsOptions options = noise_free();
  options.rate_hz = 10.0;
  options.heading_bias_sigma = rad_from_deg(0.02);
  std::vector<double> bias;
  for (const InsSample& s : simulate_ins(truth, Eigen::Isometry3d::Identity(), options, 3)) {
    bias.push_back(angle_difference(s.attitude.yaw, 0.3));
  }
  // 48 correlation times: the spread is the configured sigma within a loose statistical bound...
  EXPECT_NEAR(standard_deviation(bias) / options.heading_bias_sigma, 1.0, 0.5);
  // ...while from one sample to the next (0.1 s of 300 s) it barely moves: each step has a
  // standard deviation of sigma * sqrt(1 - exp(-2 dt / tau)) = 0.026 sigma.
  for (std::size_t i = 1; i < bias.size(); ++i) {
    ASSERT_LT(std::abs(bias[i] - bias[i - 1]), 0.2 * options.heading_bias_sigma) << i;
  }
}

TEST(InsModel, LeverArmVelocityInAConstantRateTurn) {
  const double radius = 25.0;  // [m]
  const double speed = 8.0;    // [m/s]
  VehicleStates truth;
  for (int i = 0; i <= 500; ++i) truth.push_back(circle_state(i * 0.01, radius, speed));
  const Eigen::Isometry3d vehicle_from_ins =
      make_transform(EulerAngles{0, 0, 0.05}, Eigen::Vector3d(1.5, 0.8, 1.2));
  const std::vector<InsSample> samples = simulate_ins(truth, vehicle_from_ins, noise_free(), 1);
  const Eigen::Vector3d r = vehicle_from_ins.translation();
  for (std::size_t i = 0; i < samples.size(); i += 50) {
    const VehicleState& s = truth[i];
    const Eigen::Vector3d expected =
        s.velocity_enu + s.world_from_vehicle.linear() * s.angular_velocity_vehicle.cross(r);
    EXPECT_TRUE(samples[i].velocity_enu.isApprox(expected, 1e-12)) << i;
    // Independently: the time derivative of the device's position on the circle.
    const double h = 1e-4;
    const Eigen::Vector3d derivative =
        (circle_state(s.time + h, radius, speed).world_from_vehicle * r -
         circle_state(s.time - h, radius, speed).world_from_vehicle * r) /
        (2 * h);
    EXPECT_LT((samples[i].velocity_enu - derivative).norm(), 1e-6) << i;
    // The lever arm matters: omega x r is about 0.5 m/s here.
    EXPECT_GT((samples[i].velocity_enu - s.velocity_enu).norm(), 0.1);
  }
}

TEST(InsModel, DeterministicForASeedAndDifferentAcrossSeeds) {
  const VehicleStates truth = straight_drive(5.0, 10.0, 0.5, 100.0, kStart);
  const auto a = simulate_ins(truth, kVehicleFromIns, InsOptions::sps(), 42);
  const auto b = simulate_ins(truth, kVehicleFromIns, InsOptions::sps(), 42);
  const auto c = simulate_ins(truth, kVehicleFromIns, InsOptions::sps(), 43);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].time, b[i].time);
    EXPECT_EQ(a[i].position_enu, b[i].position_enu);
    EXPECT_EQ(a[i].velocity_enu, b[i].velocity_enu);
    EXPECT_EQ(std::memcmp(&a[i].attitude, &b[i].attitude, sizeof(EulerAngles)), 0);
    EXPECT_EQ(a[i].status, kStatusSinglePoint);
  }
  EXPECT_NE(a[10].position_enu, c[10].position_enu);
}

TEST(InsModel, SamplesEveryKthStateWhenTheTruthIsFaster) {
  const VehicleStates truth = straight_drive(2.0, 10.0, 0.0, 200.0, kStart);  // 401 states
  const std::vector<InsSample> samples = simulate_ins(truth, kVehicleFromIns, noise_free(), 1);
  ASSERT_EQ(samples.size(), 201u);
  EXPECT_EQ(samples[1].time, truth[2].time);
  EXPECT_EQ(samples[200].time, truth[400].time);
  EXPECT_EQ(samples[0].status, kStatusRtkFixed);
  EXPECT_TRUE(simulate_ins({}, kVehicleFromIns, InsOptions{}, 1).empty());
}

TEST(InsModel, OptionsCheckRejectsNonsense) {
  EXPECT_NO_THROW(InsOptions::rtk().Check());
  EXPECT_NO_THROW(InsOptions::sps().Check());
  InsOptions o;
  o.rate_hz = 0.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = InsOptions{};
  o.heading_bias_tau = -1.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = InsOptions{};
  o.velocity_sigma_vertical = -0.1;
  EXPECT_THROW(simulate_ins(straight_drive(1, 1, 0, 100, kStart), kVehicleFromIns, o, 1),
               std::invalid_argument);
  VehicleStates backwards = straight_drive(1, 1, 0, 100, kStart);
  backwards.back().time = -1.0;
  EXPECT_THROW(simulate_ins(backwards, kVehicleFromIns, InsOptions{}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::sim
