#include "x2car/core/robust_stats.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

void check_weights(std::span<const double> values, std::span<const double> weights) {
  if (!weights.empty() && weights.size() != values.size()) {
    throw std::invalid_argument("values and weights differ in size");
  }
  for (const double weight : weights) {
    if (!(weight >= 0.0) || !std::isfinite(weight)) {
      throw std::invalid_argument("weights must be finite and non-negative");
    }
  }
}

// Normalised weights (sum 1); empty weights mean equal weights.
std::vector<double> normalised_weights(std::span<const double> values,
                                       std::span<const double> weights) {
  check_weights(values, weights);
  std::vector<double> normalised(values.size(), 1.0);
  if (!weights.empty()) normalised.assign(weights.begin(), weights.end());
  double total = 0.0;
  for (const double weight : normalised) total += weight;
  if (!(total > 0.0)) throw std::invalid_argument("weights sum to zero");
  for (double& weight : normalised) weight /= total;
  return normalised;
}

}  // namespace

double median(std::span<const double> values) {
  if (values.empty()) throw std::invalid_argument("median of no values");
  std::vector<double> sorted(values.begin(), values.end());
  const std::size_t middle = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + middle, sorted.end());
  const double upper = sorted[middle];
  if (sorted.size() % 2 == 1) return upper;
  const double lower = *std::max_element(sorted.begin(), sorted.begin() + middle);
  return 0.5 * (lower + upper);
}

double median_absolute_deviation(std::span<const double> values) {
  const double center = median(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (const double value : values) deviations.push_back(std::abs(value - center));
  return median(deviations);
}

double robust_sigma(std::span<const double> values) {
  return kMadToSigma * median_absolute_deviation(values);
}

void OutlierRejectionOptions::Check() const {
  const OptionsCheck check("OutlierRejectionOptions");
  check.positive("k", k);
  check.non_negative("min_sigma", min_sigma);
}

std::vector<bool> mad_inlier_mask(std::span<const double> values,
                                  const OutlierRejectionOptions& options) {
  options.Check();
  if (values.empty()) return {};
  const double center = median(values);
  const double scale = std::max(robust_sigma(values), options.min_sigma);
  const double limit = options.k * scale;
  std::vector<bool> inliers(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    inliers[i] = std::abs(values[i] - center) <= limit;
  }
  return inliers;
}

double weighted_mean(std::span<const double> values, std::span<const double> weights) {
  if (values.empty()) throw std::invalid_argument("mean of no values");
  const std::vector<double> normalised = normalised_weights(values, weights);
  double mean = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) mean += normalised[i] * values[i];
  return mean;
}

double standard_deviation(std::span<const double> values) {
  if (values.size() < 2) throw std::invalid_argument("standard deviation needs 2 or more values");
  const double mean = weighted_mean(values);
  double sum_squares = 0.0;
  for (const double value : values) sum_squares += (value - mean) * (value - mean);
  return std::sqrt(sum_squares / static_cast<double>(values.size() - 1));
}

double standard_error_of_weighted_mean(std::span<const double> estimates,
                                       std::span<const double> weights) {
  if (estimates.size() < 2) throw std::invalid_argument("standard error needs 2 or more estimates");
  const std::vector<double> normalised = normalised_weights(estimates, weights);
  const double mean = weighted_mean(estimates, weights);
  double variance = 0.0;
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    const double deviation = estimates[i] - mean;
    variance += normalised[i] * normalised[i] * deviation * deviation;
  }
  const auto n = static_cast<double>(estimates.size());
  return std::sqrt(variance * n / (n - 1.0));
}

void BootstrapOptions::Check() const {
  OptionsCheck("BootstrapOptions").at_least("resamples", resamples, 2);
}

double bootstrap_standard_error(std::span<const double> values, std::span<const double> weights,
                                const WeightedStatistic& statistic,
                                const BootstrapOptions& options) {
  options.Check();
  check_weights(values, weights);
  if (values.empty()) throw std::invalid_argument("bootstrap of no values");
  // mt19937_64 output is specified by the standard; the index is drawn by modulo (not by
  // std::uniform_int_distribution, whose algorithm differs between standard libraries) so the
  // same seed gives the same answer everywhere.
  std::mt19937_64 generator(options.seed);
  const std::size_t n = values.size();
  std::vector<double> resampled_values(n);
  std::vector<double> resampled_weights(weights.empty() ? 0 : n);
  // Spread is measured as deviations from the full-sample statistic, wrapped when it is an angle.
  const double full_sample = statistic(values, weights);
  std::vector<double> deviations;
  deviations.reserve(static_cast<std::size_t>(options.resamples));
  for (int r = 0; r < options.resamples; ++r) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t pick = static_cast<std::size_t>(generator() % n);
      resampled_values[i] = values[pick];
      if (!weights.empty()) resampled_weights[i] = weights[pick];
    }
    // A resample may put all weight on zero-weight entries; such a draw carries no information.
    if (!weights.empty() && std::all_of(resampled_weights.begin(), resampled_weights.end(),
                                        [](double weight) { return weight == 0.0; })) {
      continue;
    }
    const double deviation = statistic(resampled_values, resampled_weights) - full_sample;
    deviations.push_back(options.circular ? wrap_angle(deviation) : deviation);
  }
  if (deviations.size() < 2) throw std::invalid_argument("bootstrap: too few usable resamples");
  return standard_deviation(deviations);
}

}  // namespace x2car
