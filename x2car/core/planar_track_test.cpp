#include "x2car/core/planar_track.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

// Ground-truth plane curve parameterised by time: position [m], heading [rad], curvature [1/m].
struct TruePose {
  double x = 0.0;
  double y = 0.0;
  double heading_enu = 0.0;
  double curvature = 0.0;
};

struct NoisyTrack {
  std::vector<double> times;  // [s], ~100 Hz with jitter
  std::vector<double> x;      // [m] with noise
  std::vector<double> y;      // [m] with noise
};

// ~100 Hz with uniform time jitter of +-3 ms (GNSS stamps are not regular) and Gaussian position
// noise of sigma [m] on each axis.
NoisyTrack sample_track(const std::function<TruePose(double)>& truth, double duration_s,
                        double sigma_m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::normal_distribution<double> noise(0.0, sigma_m);
  NoisyTrack track;
  for (double nominal = 0.0; nominal <= duration_s; nominal += 0.01) {
    const double t = nominal + jitter(rng);
    const TruePose pose = truth(t);
    track.times.push_back(t);
    track.x.push_back(pose.x + noise(rng));
    track.y.push_back(pose.y + noise(rng));
  }
  return track;
}

// Circle of radius R [m] driven at v [m/s]; counter-clockwise (turning left) when `left`.
std::function<TruePose(double)> circle(double radius, double speed, bool left) {
  return [=](double t) {
    const double sign = left ? 1.0 : -1.0;
    const double angle = 0.3 + sign * speed / radius * t;  // polar angle about the centre [rad]
    return TruePose{1200.0 + radius * std::cos(angle), -800.0 + radius * std::sin(angle),
                    wrap_angle(angle + sign * kPi / 2), sign / radius};
  };
}

// Straight lead-in (50 m), clothoid with kappa = rate * s over 200 m (0 -> 0.02 1/m), then the
// arc of the final curvature; driven at 10 m/s, s = 0 at t = 5 s. Positions integrate
// cos/sin(heading) with Simpson's rule: a table every 4 cm plus one 2-panel step to s (error
// << 1 um).
std::function<TruePose(double)> clothoid() {
  constexpr double kSpeed = 10.0;
  constexpr double kRate = 1e-4;  // [1/m^2]
  constexpr double kLength = 200.0;
  constexpr double kStart = -50.0;  // arc length at t = 0 [m]
  constexpr double kStep = 0.04;    // table step [m]
  const auto heading = [=](double s) {
    if (s <= 0.0) return 0.0;
    if (s <= kLength) return 0.5 * kRate * s * s;
    return 0.5 * kRate * kLength * kLength + kRate * kLength * (s - kLength);
  };
  const auto simpson = [=](double a, double b, double& x, double& y) {
    const double m = 0.5 * (a + b);
    x += (b - a) / 6.0 * (std::cos(heading(a)) + 4 * std::cos(heading(m)) + std::cos(heading(b)));
    y += (b - a) / 6.0 * (std::sin(heading(a)) + 4 * std::sin(heading(m)) + std::sin(heading(b)));
  };
  auto table = std::make_shared<std::vector<TruePose>>(1, TruePose{kStart, 0.0, 0.0, 0.0});
  for (double s = kStart; s < kStart + kSpeed * 40.0; s += kStep) {
    TruePose next = table->back();
    simpson(s, s + kStep, next.x, next.y);
    table->push_back(next);
  }
  return [=](double t) {
    const double s = kSpeed * (t - 5.0);
    const auto k = std::size_t(std::max(0.0, std::floor((s - kStart) / kStep)));
    TruePose pose = (*table)[k];
    simpson(kStart + k * kStep, s, pose.x, pose.y);
    pose.heading_enu = wrap_angle(heading(s));
    pose.curvature = kRate * std::clamp(s, 0.0, kLength);
    return pose;
  };
}

struct TrackErrors {
  double heading_rms_deg = 0.0;
  double heading_max_deg = 0.0;
  double curvature_max = 0.0;  // max |kappa - kappa_true| [1/m]
};

// Errors of the fitted track at the sample times, `margin_s` away from both ends (the ends have
// one-sided support and are not used by calibrators without a speed/segment gate anyway).
TrackErrors track_errors(const NoisyTrack& track, const std::function<TruePose(double)>& truth,
                         double margin_s) {
  const PlanarTrack fitted = fit_planar_track(track.times, track.x, track.y, {});
  const PlanarTrackSamples samples = sample_planar_track(fitted, track.times);
  TrackErrors errors;
  double squared = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < track.times.size(); ++k) {
    const double t = track.times[k];
    if (t < track.times.front() + margin_s || t > track.times.back() - margin_s) continue;
    const TruePose pose = truth(t);
    const double heading_error =
        deg_from_rad(angle_difference(samples.heading_enu[k], pose.heading_enu));
    squared += heading_error * heading_error;
    ++count;
    errors.heading_max_deg = std::max(errors.heading_max_deg, std::abs(heading_error));
    errors.curvature_max =
        std::max(errors.curvature_max, std::abs(samples.curvature[k] - pose.curvature));
  }
  errors.heading_rms_deg = std::sqrt(squared / count);
  return errors;
}

// Circle R = 50 m at 10 m/s, 60 s (~2 laps), 2 cm noise, jittered 100 Hz. Bounds, 2 s from the
// ends: heading RMS <= 0.05 deg, max <= 0.2 deg; curvature within +-2 % of 1/R. Both turning
// directions (signed curvature: + left, - right), three seeds each.
TEST(PlanarTrack, RecoversHeadingAndCurvatureOfNoisyCircle) {
  for (bool left : {true, false}) {
    for (std::uint64_t seed : {21, 22, 23}) {
      const auto truth = circle(50.0, 10.0, left);
      const TrackErrors errors = track_errors(sample_track(truth, 60.0, 0.02, seed), truth, 2.0);
      std::printf(
          "[          ] circle %s seed %d: heading rms %.4f deg, max %.4f deg; curvature max "
          "error %.2f %% of 1/R\n",
          left ? "left " : "right", int(seed), errors.heading_rms_deg, errors.heading_max_deg,
          100.0 * errors.curvature_max * 50.0);
      EXPECT_LE(errors.heading_rms_deg, 0.05);
      EXPECT_LE(errors.heading_max_deg, 0.2);
      EXPECT_LE(errors.curvature_max, 0.02 / 50.0);
    }
  }
}

// Clothoid 0 -> 0.02 1/m over 200 m between a straight and an arc, 2 cm noise. Bounds, 2 s from
// the ends: heading RMS <= 0.05 deg, max <= 0.2 deg; |kappa - kappa_true| <= 4e-4 1/m (2 % of
// the final curvature), including the two kinks of kappa(s).
TEST(PlanarTrack, RecoversHeadingAndCurvatureOfNoisyClothoid) {
  const auto truth = clothoid();
  for (std::uint64_t seed : {31, 32, 33}) {
    const TrackErrors errors = track_errors(sample_track(truth, 35.0, 0.02, seed), truth, 2.0);
    std::printf(
        "[          ] clothoid seed %d: heading rms %.4f deg, max %.4f deg; curvature max "
        "error %.2e 1/m\n",
        int(seed), errors.heading_rms_deg, errors.heading_max_deg, errors.curvature_max);
    EXPECT_LE(errors.heading_rms_deg, 0.05);
    EXPECT_LE(errors.heading_max_deg, 0.2);
    EXPECT_LE(errors.curvature_max, 4e-4);
  }
}

// Driving west: the heading sits on the +-pi seam and must stay in (-pi, pi] and close to pi.
TEST(PlanarTrack, HeadingIsWrappedAcrossTheSeam) {
  const auto west = [](double t) { return TruePose{-8.0 * t, 3.0, kPi, 0.0}; };
  const NoisyTrack track = sample_track(west, 20.0, 0.02, 41);
  const PlanarTrack fitted = fit_planar_track(track.times, track.x, track.y, {});
  for (double t = 1.0; t < 19.0; t += 0.1) {
    const PlanarTrackState state = fitted.state(t);
    EXPECT_GT(state.heading_enu, -kPi);
    EXPECT_LE(state.heading_enu, kPi);
    EXPECT_LT(std::abs(deg_from_rad(angle_difference(state.heading_enu, kPi))), 0.1);
    EXPECT_NEAR(state.speed, 8.0, 0.01);
    EXPECT_NEAR(state.curvature, 0.0, 1e-4);
  }
}

// At standstill heading and curvature are meaningless but finite; speed tells the caller.
TEST(PlanarTrack, StandstillGivesFiniteStateWithNearZeroSpeed) {
  const auto parked = [](double) { return TruePose{5.0, -2.0, 0.0, 0.0}; };
  const NoisyTrack track = sample_track(parked, 10.0, 0.02, 42);
  const PlanarTrack fitted = fit_planar_track(track.times, track.x, track.y, {});
  for (double t = 0.0; t < 10.0; t += 0.05) {
    const PlanarTrackState state = fitted.state(t);
    EXPECT_LT(state.speed, 0.05);
    EXPECT_TRUE(std::isfinite(state.heading_enu));
    EXPECT_TRUE(std::isfinite(state.curvature));
  }
}

TEST(PlanarTrack, SamplesMatchStateAndRejectBadInput) {
  const auto truth = circle(30.0, 5.0, true);
  const NoisyTrack track = sample_track(truth, 10.0, 0.01, 43);
  const PlanarTrack fitted = fit_planar_track(track.times, track.x, track.y, {});
  const std::vector<double> times = {2.0, 1.0, 7.5};
  const PlanarTrackSamples samples = sample_planar_track(fitted, times);
  ASSERT_EQ(samples.curvature.size(), times.size());
  for (std::size_t k = 0; k < times.size(); ++k) {
    const PlanarTrackState state = fitted.state(times[k]);
    EXPECT_EQ(samples.time[k], times[k]);
    EXPECT_EQ(samples.x[k], state.x);
    EXPECT_EQ(samples.y[k], state.y);
    EXPECT_EQ(samples.speed[k], state.speed);
    EXPECT_EQ(samples.heading_enu[k], state.heading_enu);
    EXPECT_EQ(samples.curvature[k], state.curvature);
  }
  EXPECT_EQ(fitted.x_spline().smoothing(), fitted.y_spline().smoothing());
  std::vector<double> short_y(track.y.begin(), track.y.end() - 1);
  EXPECT_THROW(fit_planar_track(track.times, track.x, short_y, {}), std::invalid_argument);
  PlanarTrackOptions options;
  options.spline.knot_spacing_s = -1.0;
  EXPECT_THROW(fit_planar_track(track.times, track.x, track.y, options), std::invalid_argument);
}

// 10 min at 100 Hz (60 000 samples, ~1 200 coefficients) with GCV; its speed is measured in
// bench/core_bench.cpp (BM_SmoothTrackWithGcv, BM_SampleAndSegmentTrack).
TEST(PlanarTrack, FitsTenMinutesAt100Hz) {
  const auto weave = [](double t) {
    return TruePose{10.0 * t + 30.0 * std::sin(0.05 * t), 40.0 * std::sin(0.03 * t), 0.0, 0.0};
  };
  const NoisyTrack track = sample_track(weave, 600.0, 0.02, 44);
  ASSERT_GE(track.times.size(), 60000u);
  const PlanarTrack fitted = fit_planar_track(track.times, track.x, track.y, {});
  const PlanarTrackSamples samples = sample_planar_track(fitted, track.times);
  EXPECT_NEAR(fitted.x_spline().residual_std(), 0.02, 0.004);
  EXPECT_EQ(samples.time.size(), track.times.size());
}

}  // namespace
}  // namespace x2car
