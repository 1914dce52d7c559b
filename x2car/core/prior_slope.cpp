#include "x2car/core/prior_slope.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "x2car/core/options_check.hpp"

namespace x2car {

void SlopePrior::Check() const {
  OptionsCheck check("SlopePrior");
  check.finite("mean", mean);
  check.positive("standard_deviation", standard_deviation);
}

OffsetWithSlope offset_with_prior_slope(std::span<const double> times,
                                        std::span<const double> values,
                                        std::span<const double> regressor,
                                        const std::vector<bool>& use, const SlopePrior& prior,
                                        const MovingBlockOptions& blocks, double floor) {
  prior.Check();
  if (!(floor >= 0.0)) throw std::invalid_argument("offset_with_prior_slope: floor must be >= 0");
  if (values.size() != times.size() || regressor.size() != times.size() ||
      use.size() != times.size()) {
    throw std::invalid_argument("offset_with_prior_slope: spans of different lengths");
  }
  std::vector<double> used_times, used_values, used_x;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!use[i]) continue;
    used_times.push_back(times[i]);
    used_values.push_back(values[i]);
    used_x.push_back(regressor[i]);
  }
  const std::size_t n = used_values.size();
  if (n < 2) throw std::invalid_argument("offset_with_prior_slope: fewer than 2 used samples");
  double mean_v = 0.0, mean_x = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    mean_v += used_values[i];
    mean_x += used_x[i];
  }
  mean_v /= static_cast<double>(n);
  mean_x /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (used_x[i] - mean_x) * (used_x[i] - mean_x);
    sxy += (used_x[i] - mean_x) * (used_values[i] - mean_v);
  }
  const double prior_precision = 1.0 / (prior.standard_deviation * prior.standard_deviation);
  // Two passes: the residuals' variance and correlation depend on the slope, which depends on
  // them; the prior's slope is a good enough start for the first.
  double slope = prior.mean;
  double data_precision_per_variance = 0.0;  // 1 / (s^2 k)
  SeriesStandardError noise;
  std::vector<double> residuals(n);
  for (int pass = 0; pass < 2; ++pass) {
    double variance = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      residuals[i] = used_values[i] - mean_v - slope * (used_x[i] - mean_x);
      variance += residuals[i] * residuals[i];
    }
    variance /= static_cast<double>(std::max<std::size_t>(n - 1, 1));
    noise = series_standard_error(used_times, residuals, blocks);
    // k: how many times the residuals' mean varies more than independent samples' would.
    const double independent_variance_of_mean = variance / static_cast<double>(n);
    const double inflation =
        independent_variance_of_mean > 0.0
            ? std::max(1.0, noise.combined * noise.combined / independent_variance_of_mean)
            : 1.0;
    data_precision_per_variance = variance > 0.0 ? 1.0 / (variance * inflation) : 0.0;
    if (data_precision_per_variance == 0.0) break;  // a perfect fit: the data say nothing more
    slope = (prior.mean * prior_precision + sxy * data_precision_per_variance) /
            (prior_precision + sxx * data_precision_per_variance);
  }
  OffsetWithSlope fit;
  fit.slope = slope;
  fit.slope_std = 1.0 / std::sqrt(prior_precision + sxx * data_precision_per_variance);
  fit.offset = mean_v - slope * mean_x;
  fit.noise_standard_error = noise.combined;
  fit.standard_error = std::sqrt(noise.combined * noise.combined +
                                 mean_x * mean_x * fit.slope_std * fit.slope_std + floor * floor);
  return fit;
}

}  // namespace x2car
