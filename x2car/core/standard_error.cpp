#include "x2car/core/standard_error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"

namespace x2car {
namespace {

constexpr double kZ975 = 1.959963984540054;  // Phi^-1(0.975)

// t_{0.975, dof} for dof = 1 .. 30.
constexpr std::array<double, 30> kT975{
    12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281,
    2.2010,  2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930, 2.0860,
    2.0796,  2.0739, 2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423};

// Cornish-Fisher expansion of the t quantile in 1 / dof; within 1e-4 of the exact value for
// dof >= 30.
double t975_expansion(double dof) {
  const double z = kZ975, z3 = z * z * z, z5 = z3 * z * z;
  return z + (z3 + z) / (4.0 * dof) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * dof * dof);
}

double t975(double dof) {
  if (dof >= 30.0) return t975_expansion(dof);
  // Linear in 1 / dof between the tabulated integers: t is close to linear in 1 / dof.
  const int below = static_cast<int>(std::floor(dof));
  if (static_cast<double>(below) == dof) return kT975[static_cast<std::size_t>(below - 1)];
  const double t_below = kT975[static_cast<std::size_t>(below - 1)];
  const double t_above = kT975[static_cast<std::size_t>(below)];
  const double u = (1.0 / below - 1.0 / dof) / (1.0 / below - 1.0 / (below + 1));
  return t_below + u * (t_above - t_below);
}

// Samples per block: block_s over the median time between samples (gaps between segments do not
// count), at least 1.
double samples_per_block(std::span<const double> times, double block_s) {
  std::vector<double> steps;
  steps.reserve(times.size());
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (times[i] > times[i - 1]) steps.push_back(times[i] - times[i - 1]);
  }
  if (steps.empty()) return 1.0;
  return std::max(1.0, std::round(block_s / median(steps)));
}

}  // namespace

double small_sample_factor(double degrees_of_freedom) {
  if (!(degrees_of_freedom >= 1.0)) {
    throw std::invalid_argument("small_sample_factor: degrees of freedom must be >= 1");
  }
  return t975(degrees_of_freedom) / kZ975;
}

void MovingBlockOptions::Check() const {
  OptionsCheck("MovingBlockOptions").positive("block_s", block_s);
}

MovingBlockStandardError moving_block_standard_error(std::span<const double> times,
                                                     std::span<const double> values,
                                                     const MovingBlockOptions& options) {
  options.Check();
  if (times.size() != values.size()) {
    throw std::invalid_argument("moving_block_standard_error: times and values differ in size");
  }
  if (values.size() < 2) {
    throw std::invalid_argument("moving_block_standard_error: needs 2 or more values");
  }
  const std::size_t n = values.size();
  MovingBlockStandardError result;
  // A series shorter than two blocks is cut into two: its correlation over more than half its
  // length cannot be seen, and the few degrees of freedom (1.5) say how little that is.
  result.block_samples =
      std::min(samples_per_block(times, options.block_s), std::floor(static_cast<double>(n) / 2.0));
  const auto block = static_cast<std::size_t>(result.block_samples);
  if (block < 2) {
    result.standard_error = standard_deviation(values) / std::sqrt(static_cast<double>(n));
    return result;
  }
  const double mean = weighted_mean(values);
  // Prefix sums of the deviations from the mean: each block's mean in O(1).
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + (values[i] - mean);
  double sum_squares = 0.0;
  for (std::size_t j = 0; j + block <= n; ++j) {
    const double block_mean = (prefix[j + block] - prefix[j]) / static_cast<double>(block);
    sum_squares += block_mean * block_mean;
  }
  const double l = static_cast<double>(block), count = static_cast<double>(n);
  const double variance = l * sum_squares / ((count - l + 1.0) * (count - l));
  result.standard_error = std::sqrt(std::max(variance, 0.0));
  result.degrees_of_freedom = 1.5 * (count / l - 1.0);
  return result;
}

SeriesStandardError series_standard_error(std::span<const double> times,
                                          std::span<const double> values,
                                          const MovingBlockOptions& options, double floor) {
  if (!(floor >= 0.0)) throw std::invalid_argument("series_standard_error: floor must be >= 0");
  const MovingBlockStandardError blocks = moving_block_standard_error(times, values, options);
  SeriesStandardError result;
  result.block = blocks.degrees_of_freedom >= 1.0
                     ? small_sample_factor(blocks.degrees_of_freedom) * blocks.standard_error
                     : blocks.standard_error;
  result.formal = standard_deviation(values) / std::sqrt(static_cast<double>(values.size()));
  result.combined = std::hypot(std::max(result.block, result.formal), floor);
  return result;
}

double combined_standard_error(std::span<const double> data_standard_errors, double floor) {
  double largest = 0.0;
  for (const double se : data_standard_errors) largest = std::max(largest, se);
  return std::hypot(largest, floor);
}

}  // namespace x2car
