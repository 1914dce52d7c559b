#include "x2car/core/pspline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace x2car {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// Times k * step + uniform jitter in [-0.3, 0.3] * step on [start, end): irregular but increasing.
std::vector<double> jittered_times(double start, double end, double step, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3 * step, 0.3 * step);
  std::vector<double> times;
  for (double t = start; t < end; t += step) times.push_back(t + jitter(rng));
  return times;
}

std::vector<double> sample(const std::vector<double>& times, const std::function<double(double)>& f,
                           double noise_sigma = 0.0, std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sigma > 0.0 ? noise_sigma : 1.0);
  std::vector<double> values;
  for (double t : times) values.push_back(f(t) + (noise_sigma > 0.0 ? noise(rng) : 0.0));
  return values;
}

PSplineOptions fixed_smoothing(double lambda) {
  PSplineOptions options;
  options.smoothing = lambda;
  return options;
}

double rms_error(const PSpline& spline, const std::vector<double>& times,
                 const std::function<double(double)>& truth) {
  double squared_error = 0.0;
  for (double t : times) squared_error += std::pow(spline.value(t) - truth(t), 2);
  return std::sqrt(squared_error / times.size());
}

// The smallest RMS error against the truth over fixed lambdas 10^-3 .. 10^7 (quarter decades).
double best_rms_error(const std::vector<double>& times, const std::vector<double>& values,
                      const std::function<double(double)>& truth) {
  double best = std::numeric_limits<double>::infinity();
  for (double log10_lambda = -3.0; log10_lambda <= 7.0; log10_lambda += 0.25) {
    const PSpline spline = fit_pspline(times, values, fixed_smoothing(std::pow(10, log10_lambda)));
    best = std::min(best, rms_error(spline, times, truth));
  }
  return best;
}

TEST(PSplineOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(PSplineOptions{}.Check());
  const auto expect_rejects = [](PSplineOptions options, const char* field) {
    try {
      options.Check();
      ADD_FAILURE() << "accepted bad " << field;
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(field), std::string::npos) << error.what();
    }
  };
  PSplineOptions options;
  options.degree = 2;
  expect_rejects(options, "degree");
  options.degree = 6;
  expect_rejects(options, "degree");
  options = {};
  options.penalty_order = 0;
  expect_rejects(options, "penalty_order");
  options.penalty_order = 4;  // > degree 3
  expect_rejects(options, "penalty_order");
  options = {};
  options.knot_spacing_s = 0.0;
  expect_rejects(options, "knot_spacing_s");
  options = {};
  options.smoothing = -1.0;
  expect_rejects(options, "smoothing");
  options.smoothing = std::numeric_limits<double>::quiet_NaN();
  expect_rejects(options, "smoothing");
  options = {};
  options.gcv_log10_min = 3.0;
  options.gcv_log10_max = 3.0;
  expect_rejects(options, "gcv_log10_min");
}

// With lambda -> 0 the fit is least squares in the spline space, which contains the cubics:
// a cubic is reproduced to rounding (tolerance 1e-6 on values of size ~100).
TEST(PSpline, ReproducesPolynomialOfItsDegreeWithTinySmoothing) {
  const auto cubic = [](double t) { return 1.0 + 2.0 * t - 0.5 * t * t + 0.1 * t * t * t; };
  const auto times = jittered_times(0.0, 10.0, 0.05, 7);
  const PSpline spline = fit_pspline(times, sample(times, cubic), fixed_smoothing(1e-9));
  for (double t = times.front(); t <= times.back(); t += 0.013) {
    EXPECT_NEAR(spline.value(t), cubic(t), 1e-6) << "t=" << t;
    EXPECT_NEAR(spline.derivative(t, 1), 2.0 - t + 0.3 * t * t, 1e-5) << "t=" << t;
    EXPECT_NEAR(spline.derivative(t, 2), -1.0 + 0.6 * t, 1e-4) << "t=" << t;
  }
}

// Polynomials of degree < penalty_order are in the penalty's null space: any lambda leaves them
// exact (here lambda / mean diagonal of B'WB ~ 1e7, the heavy end of the GCV range; tolerance
// 1e-6 on values 1000..1066, i.e. 1e-8 of their range, allows for the system's conditioning
// there), and tr H -> penalty_order as lambda -> inf.
TEST(PSpline, HeavySmoothingKeepsPolynomialsBelowPenaltyOrder) {
  const auto quadratic = [](double t) { return 1000.0 - 0.7 * t + 0.2 * t * t; };
  const auto times = jittered_times(0.0, 20.0, 0.1, 8);
  const auto values = sample(times, quadratic);
  const PSpline spline = fit_pspline(times, values, fixed_smoothing(3e7));
  for (double t = 0.1; t < 19.9; t += 0.37) EXPECT_NEAR(spline.value(t), quadratic(t), 1e-6);
  EXPECT_NEAR(fit_pspline(times, values, fixed_smoothing(1e12)).effective_dof(), 3.0, 1e-3);
}

// The derivative recursion must agree with central differences of value(); the difference
// quotient's error is O(delta^2 f''') + rounding, well below 1e-6 here.
TEST(PSpline, DerivativesMatchFiniteDifferencesOfValue) {
  const auto times = jittered_times(0.0, 15.0, 0.01, 9);
  const PSpline spline = fit_pspline(times,
                                     sample(
                                         times, [](double t) { return std::sin(t); }, 0.05, 9),
                                     {});
  const double delta = 1e-4;
  for (double t = 0.2; t < 14.8; t += 0.0917) {
    const double d1 = (spline.value(t + delta) - spline.value(t - delta)) / (2 * delta);
    const double d2 =
        (spline.derivative(t + delta, 1) - spline.derivative(t - delta, 1)) / (2 * delta);
    EXPECT_NEAR(spline.derivative(t, 1), d1, 1e-6) << "t=" << t;
    EXPECT_NEAR(spline.derivative(t, 2), d2, 1e-5) << "t=" << t;
  }
  EXPECT_THROW(spline.derivative(1.0, 3), std::invalid_argument);
}

// Noise-free smooth function, 0.1 s knots: cubic-spline approximation errors are O(h^4 f''''),
// O(h^3), O(h^2) for value and derivatives; measured 1.4e-7, 8e-6, 7.7e-4, bounds 1e-6, 1e-4,
// 5e-3.
TEST(PSpline, DerivativesMatchAnalyticOnSmoothFunction) {
  const auto times = jittered_times(0.0, 12.0, 0.01, 10);
  PSplineOptions options = fixed_smoothing(1e-6);
  options.knot_spacing_s = 0.1;
  const PSpline spline = fit_pspline(
      times, sample(times, [](double t) { return std::sin(t) + 0.3 * t * t; }), options);
  double max_error[3] = {0, 0, 0};
  for (double t = 0.5; t < 11.5; t += 0.0123) {
    max_error[0] = std::max(max_error[0], std::abs(spline.value(t) - std::sin(t) - 0.3 * t * t));
    max_error[1] =
        std::max(max_error[1], std::abs(spline.derivative(t, 1) - std::cos(t) - 0.6 * t));
    max_error[2] = std::max(max_error[2], std::abs(spline.derivative(t, 2) + std::sin(t) - 0.6));
  }
  std::printf("[          ] smooth function max errors: value %.2e, d1 %.2e, d2 %.2e\n",
              max_error[0], max_error[1], max_error[2]);
  EXPECT_LT(max_error[0], 1e-6);
  EXPECT_LT(max_error[1], 1e-4);
  EXPECT_LT(max_error[2], 5e-3);
}

// GCV on a noisy sine (sigma 0.1, 100 Hz, 30 s): the residual std estimates sigma within +-20 %,
// and the smooth is nearly as close to the truth as with the best lambda in hindsight (RMS error
// within 1.3x of the best on a grid of fixed lambdas, and < 0.25 sigma).
TEST(PSpline, GcvChoosesReasonableSmoothingOnNoisySine) {
  const double sigma = 0.1;
  const auto truth = [](double t) { return std::sin(kTwoPi * t / 5.0); };
  for (std::uint64_t seed : {11, 12, 13}) {
    const auto times = jittered_times(0.0, 30.0, 0.01, seed);
    const PSpline spline = fit_pspline(times, sample(times, truth, sigma, seed), {});
    const double error = rms_error(spline, times, truth);
    const double best = best_rms_error(times, sample(times, truth, sigma, seed), truth);
    std::printf(
        "[          ] seed %d: lambda %.3g, dof %.1f, residual std %.4f, rms error %.4f (best "
        "fixed lambda %.4f)\n",
        int(seed), spline.smoothing(), spline.effective_dof(), spline.residual_std(), error, best);
    EXPECT_NEAR(spline.residual_std(), sigma, 0.2 * sigma);
    EXPECT_LT(error, 0.25 * sigma);
    EXPECT_LT(error, 1.3 * best);
  }
}

// A 2 s gap in a slow sine with noise sigma 0.02: the penalty bridges it smoothly (error < 0.02
// inside the gap, where the sine moves by 0.6; measured 0.003), and elsewhere the fit stays
// within half the noise of the truth (measured 0.004).
TEST(PSpline, IrregularSamplingWithGap) {
  const auto truth = [](double t) { return std::sin(kTwoPi * t / 20.0); };
  std::vector<double> times;
  for (double t : jittered_times(0.0, 40.0, 0.02, 14)) {
    if (t < 19.0 || t > 21.0) times.push_back(t);
  }
  const PSpline spline = fit_pspline(times, sample(times, truth, 0.02, 14), {});
  double max_gap_error = 0.0;
  double max_data_error = 0.0;
  for (double t = 1.0; t < 39.0; t += 0.01) {
    double& max_error = (t > 19.0 && t < 21.0) ? max_gap_error : max_data_error;
    max_error = std::max(max_error, std::abs(spline.value(t) - truth(t)));
  }
  std::printf("[          ] gap: max error in gap %.4f, elsewhere %.4f\n", max_gap_error,
              max_data_error);
  EXPECT_LT(max_gap_error, 0.02);
  EXPECT_LT(max_data_error, 0.01);
}

// Zero weights remove samples exactly: same knots (interior samples) and lambda give the same fit
// as dropping them. Scaling all weights and lambda together leaves the fit unchanged.
TEST(PSpline, WeightedFit) {
  const auto times = jittered_times(0.0, 10.0, 0.02, 15);
  auto values = sample(
      times, [](double t) { return std::cos(t); }, 0.01, 15);
  std::vector<double> weights(times.size(), 1.0);
  std::vector<double> kept_times;
  std::vector<double> kept_values;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (k % 7 == 3 && k + 1 < times.size()) {  // the last sample keeps the span
      values[k] += 50.0;                       // outlier, weight 0
      weights[k] = 0.0;
    } else {
      kept_times.push_back(times[k]);
      kept_values.push_back(values[k]);
    }
  }
  const PSpline weighted = fit_pspline(times, values, fixed_smoothing(10.0), weights);
  const PSpline dropped = fit_pspline(kept_times, kept_values, fixed_smoothing(10.0));
  for (std::size_t i = 0; i < weighted.coefficients().size(); ++i) {
    EXPECT_NEAR(weighted.coefficients()[i], dropped.coefficients()[i], 1e-9);
  }
  EXPECT_NEAR(weighted.effective_dof(), dropped.effective_dof(), 1e-9);

  std::vector<double> scaled(weights);
  for (double& w : scaled) w *= 400.0;
  const PSpline scaled_fit = fit_pspline(times, values, fixed_smoothing(4000.0), scaled);
  EXPECT_NEAR(scaled_fit.value(5.0), weighted.value(5.0), 1e-9);
  EXPECT_NEAR(scaled_fit.residual_std(), 20.0 * weighted.residual_std(), 1e-9);
  // GCV is invariant to the weights' scale too.
  EXPECT_NEAR(fit_pspline(times, values, {}, scaled).value(5.0),
              fit_pspline(times, values, {}, weights).value(5.0), 1e-6);
}

// tr H from the Takahashi recursion equals the brute-force trace: column k of H is the fit of the
// unit vector e_k, so H_kk is that fit evaluated at t_k.
TEST(PSpline, EffectiveDofMatchesBruteForceTrace) {
  const auto times = jittered_times(0.0, 6.0, 0.15, 16);
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> uniform(0.2, 3.0);
  std::vector<double> weights;
  for (std::size_t k = 0; k < times.size(); ++k) weights.push_back(uniform(rng));
  for (int degree : {3, 4, 5}) {
    PSplineOptions options = fixed_smoothing(0.7);
    options.degree = degree;
    options.penalty_order = 2;
    double trace = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      std::vector<double> unit(times.size(), 0.0);
      unit[k] = 1.0;
      trace += fit_pspline(times, unit, options, weights).value(times[k]);
    }
    const auto any_values = sample(times, [](double t) { return std::sin(t); });  // tr H: no y
    const double dof = fit_pspline(times, any_values, options, weights).effective_dof();
    EXPECT_NEAR(dof, trace, 1e-8) << "degree " << degree;
  }
}

// Series sharing times and lambda: two copies of one series choose the lambda the single series
// chooses (the summed GCV is twice the single one).
TEST(PSpline, SharedSmoothingForSeveralSeries) {
  const auto times = jittered_times(0.0, 20.0, 0.01, 17);
  const auto a = sample(
      times, [](double t) { return std::sin(t); }, 0.05, 17);
  const auto b = sample(
      times, [](double t) { return 0.1 * t * t; }, 0.05, 18);
  const PSpline single = fit_pspline(times, a, {});
  const std::array<std::span<const double>, 2> twice = {a, a};
  const auto pair = fit_psplines_shared(times, twice, {});
  ASSERT_EQ(pair.size(), 2u);
  EXPECT_NEAR(std::log10(pair[0].smoothing()), std::log10(single.smoothing()), 1e-6);
  EXPECT_NEAR(pair[1].value(7.0), single.value(7.0), 1e-9);

  const std::array<std::span<const double>, 2> both = {a, b};
  const auto mixed = fit_psplines_shared(times, both, {});
  EXPECT_EQ(mixed[0].smoothing(), mixed[1].smoothing());
  EXPECT_EQ(mixed[0].effective_dof(), mixed[1].effective_dof());
  EXPECT_NEAR(mixed[1].value(10.0), 10.0, 0.05);
}

// Outside the span, values and derivatives are those at the nearest end.
TEST(PSpline, ClampsOutsideTheSpan) {
  const auto times = jittered_times(1.0, 5.0, 0.05, 19);
  const PSpline spline =
      fit_pspline(times, sample(times, [](double t) { return t * t; }), fixed_smoothing(1e-6));
  EXPECT_DOUBLE_EQ(spline.start_time(), times.front());
  EXPECT_DOUBLE_EQ(spline.end_time(), times.back());
  EXPECT_EQ(spline.value(-100.0), spline.value(times.front()));
  EXPECT_EQ(spline.derivative(100.0, 1), spline.derivative(times.back(), 1));
  EXPECT_TRUE(spline.contains(3.0));
  EXPECT_FALSE(spline.contains(100.0));
}

TEST(PSpline, RejectsBadInput) {
  const auto times = jittered_times(0.0, 1.0, 0.1, 20);
  const auto values = sample(times, [](double t) { return t; });
  const auto expect_message = [](const std::function<void()>& fit, const char* text) {
    try {
      fit();
      ADD_FAILURE() << "accepted input that should fail with '" << text << "'";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(text), std::string::npos) << error.what();
    }
  };
  const std::vector<double> four(times.begin(), times.begin() + 4);
  expect_message([&] { fit_pspline(four, std::vector<double>(4, 1.0), {}); }, "need at least 5");
  auto bad = values;
  bad[3] = std::numeric_limits<double>::quiet_NaN();
  expect_message([&] { fit_pspline(times, bad, {}); }, "value 3 of series 0 is not finite");
  auto bad_times = times;
  bad_times[2] = std::numeric_limits<double>::infinity();
  expect_message([&] { fit_pspline(bad_times, values, {}); }, "time 2 is not finite");
  bad_times = times;
  bad_times[5] = bad_times[4];
  expect_message([&] { fit_pspline(bad_times, values, {}); }, "strictly increasing");
  expect_message([&] { fit_pspline(times, four, {}); }, "has 4 values for");
  std::vector<double> weights(times.size(), 1.0);
  weights[1] = -1.0;
  expect_message([&] { fit_pspline(times, values, {}, weights); }, "weight 1 is -1");
  expect_message([&] { fit_pspline(times, values, {}, std::vector<double>(times.size(), 0.0)); },
                 "0 samples with positive weight");
  PSplineOptions options;
  options.degree = 7;
  expect_message([&] { fit_pspline(times, values, options); }, "degree must be in [3, 5] (got 7)");
}

}  // namespace
}  // namespace x2car
