#include "x2car/core/turn_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

// |kappa r_x| is kept below 1 (a sensor ahead of the point the car turns about); a turn that
// tight is no road's.
constexpr double kMaxSine = 0.99;

// One sample of the fit: kappa [1/m] and the offset relative to the fit's centre [rad].
struct FitSample {
  double curvature = 0.0;
  double offset = 0.0;
};

// The fit's state: intercept a [rad] and lever arm r [m], with the normal matrix of the last step.
struct FitState {
  double a = 0.0;
  double r = 0.0;
  double h11 = 0.0, h12 = 0.0, h22 = 0.0;  // J^T J
  bool identifiable = false;
};

double sine_of_shift(double curvature, double lever_arm_x) {
  return std::clamp(curvature * lever_arm_x, -kMaxSine, kMaxSine);
}

double residual(const FitSample& sample, const FitState& state) {
  return sample.offset - (state.a - std::asin(sine_of_shift(sample.curvature, state.r)));
}

// Gauss-Newton on offset = a - asin(kappa r) over the inliers; r stays where it is when kappa does
// not vary (then only a is fitted).
void gauss_newton(std::span<const FitSample> samples, const std::vector<bool>& inlier,
                  FitState& state) {
  constexpr int kMaxIterations = 10;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    double h11 = 0.0, h12 = 0.0, h22 = 0.0, g1 = 0.0, g2 = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!inlier[i]) continue;
      const double u = sine_of_shift(samples[i].curvature, state.r);
      const double j2 = -samples[i].curvature / std::sqrt(1.0 - u * u);  // d model / d r
      const double e = residual(samples[i], state);
      h11 += 1.0;
      h12 += j2;
      h22 += j2 * j2;
      g1 += e;
      g2 += j2 * e;
    }
    state.h11 = h11;
    state.h12 = h12;
    state.h22 = h22;
    const double determinant = h11 * h22 - h12 * h12;
    state.identifiable = h11 >= 3.0 && determinant > 1e-12 * h11 * h22 && h22 > 0.0;
    if (!state.identifiable) {
      if (h11 > 0.0) state.a += g1 / h11;
      return;
    }
    const double da = (h22 * g1 - h12 * g2) / determinant;
    const double dr = (h11 * g2 - h12 * g1) / determinant;
    state.a += da;
    state.r += dr;
    if (std::abs(dr) < 1e-6 && std::abs(da) < 1e-10) return;
  }
}

std::vector<bool> inliers_of(std::span<const FitSample> samples, const FitState& state,
                             const LeverArmFitOptions& options) {
  std::vector<double> residuals(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) residuals[i] = residual(samples[i], state);
  return mad_inlier_mask(residuals,
                         {.k = options.outlier_k, .min_sigma = options.outlier_min_sigma});
}

}  // namespace

std::vector<double> lever_arm_heading_shift(std::span<const double> yaw_rate_curvature,
                                            double lever_arm_x) {
  std::vector<double> shift(yaw_rate_curvature.size());
  for (std::size_t i = 0; i < shift.size(); ++i) {
    shift[i] = std::isfinite(yaw_rate_curvature[i])
                   ? std::asin(sine_of_shift(yaw_rate_curvature[i], lever_arm_x))
                   : std::nan("");
  }
  return shift;
}

void LeverArmFitOptions::Check() const {
  const OptionsCheck check("LeverArmFitOptions");
  check.positive("outlier_k", outlier_k);
  check.non_negative("outlier_min_sigma", outlier_min_sigma);
  check.positive("correlation_s", correlation_s);
}

LeverArmFit fit_lever_arm_x(std::span<const double> offsets,
                            std::span<const double> yaw_rate_curvature,
                            const Segmentation& segments, const LeverArmFitOptions& options) {
  options.Check();
  std::vector<FitSample> samples;
  std::vector<double> raw_offsets;
  double duration = 0.0;
  for (const TimeSegment& segment : segments.segments) {
    duration += segment.duration();
    for (std::size_t i = segment.begin; i < segment.end; ++i) {
      if (!std::isfinite(offsets[i]) || !std::isfinite(yaw_rate_curvature[i])) continue;
      samples.push_back({yaw_rate_curvature[i], 0.0});
      raw_offsets.push_back(offsets[i]);
    }
  }
  LeverArmFit fit;
  if (samples.size() < 3 || mean_resultant_length(raw_offsets) < 1e-6) return fit;
  // Offsets relative to their circular mean: no seam inside the fit.
  const double centre = circular_mean(raw_offsets);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    samples[i].offset = angle_difference(raw_offsets[i], centre);
  }
  FitState state;
  std::vector<bool> inlier(samples.size(), true);
  // Fit, reject by the residuals, refit; twice, so that a first fit pulled by outliers does not
  // decide alone which samples are outliers.
  gauss_newton(samples, inlier, state);
  for (int pass = 0; pass < 2; ++pass) {
    inlier = inliers_of(samples, state, options);
    gauss_newton(samples, inlier, state);
  }
  double sum_residual2 = 0.0, sum_curvature = 0.0, sum_curvature2 = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!inlier[i]) continue;
    const double e = residual(samples[i], state);
    sum_residual2 += e * e;
    sum_curvature += samples[i].curvature;
    sum_curvature2 += samples[i].curvature * samples[i].curvature;
  }
  const double n = state.h11;
  fit.samples = static_cast<std::int64_t>(n);
  fit.outliers = static_cast<std::int64_t>(samples.size()) - fit.samples;
  fit.yaw = wrap_angle(centre + state.a);
  if (n < 3.0) return fit;
  fit.residual_sigma = std::sqrt(sum_residual2 / (n - 2.0));
  fit.mean_curvature = sum_curvature / n;
  fit.curvature_spread =
      std::sqrt(std::max(0.0, sum_curvature2 / n - fit.mean_curvature * fit.mean_curvature));
  if (!state.identifiable) return fit;
  fit.lever_arm_x = state.r;
  // Covariance of r: sigma^2 (J^T J)^-1_rr, scaled by n / n_eff for correlated neighbours.
  const double effective = std::clamp(duration / options.correlation_s, 1.0, n);
  const double information_r = state.h22 - state.h12 * state.h12 / state.h11;
  fit.lever_arm_x_std = fit.residual_sigma * std::sqrt(n / effective / information_r);
  return fit;
}

}  // namespace x2car
