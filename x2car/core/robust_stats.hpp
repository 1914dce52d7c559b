// Robust statistics for per-sample and per-segment estimates: median, MAD, outlier rejection,
// weighted means and their standard errors, and a seeded bootstrap.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace x2car {

// Scale factor that turns the median absolute deviation into a standard deviation for normally
// distributed data: 1 / Phi^-1(3/4).
constexpr double kMadToSigma = 1.482602218505602;

// Median; the mean of the two middle values for an even count. Throws std::invalid_argument on
// empty input.
double median(std::span<const double> values);

// Median absolute deviation from the median (unscaled).
double median_absolute_deviation(std::span<const double> values);

// kMadToSigma * MAD: a standard deviation that ignores up to half the data as outliers.
double robust_sigma(std::span<const double> values);

struct OutlierRejectionOptions {
  // A value is an outlier when |x - median| > k * max(kMadToSigma * MAD, min_sigma).
  double k = 3.0;
  // Floor on the scale, in the values' unit, so that data with MAD = 0 (many equal values) does
  // not reject every value that differs at all.
  double min_sigma = 0.0;

  void Check() const;
};

// true = inlier. Empty input gives an empty mask.
std::vector<bool> mad_inlier_mask(std::span<const double> values,
                                  const OutlierRejectionOptions& options = {});

// Weighted mean; weights empty = all 1. Throws on size mismatch, negative weights or zero total.
double weighted_mean(std::span<const double> values, std::span<const double> weights = {});

// Sample standard deviation (n - 1 in the denominator); needs at least 2 values.
double standard_deviation(std::span<const double> values);

// Standard error of the weighted mean of independent per-segment estimates, from their spread:
// with normalised weights w_i, SE^2 = n / (n - 1) * sum w_i^2 (x_i - mean)^2, which for equal
// weights is s^2 / n. Needs at least 2 estimates.
double standard_error_of_weighted_mean(std::span<const double> estimates,
                                       std::span<const double> weights = {});

// A statistic of (values, weights); weights may be empty.
using WeightedStatistic =
    std::function<double(std::span<const double> values, std::span<const double> weights)>;

struct BootstrapOptions {
  int resamples = 1000;    // number of resamples with replacement
  std::uint64_t seed = 1;  // the same seed gives the same answer
  // The statistic is an angle [rad]: its spread is measured on the circle, so resampled values
  // on both sides of the +-pi seam count as close.
  bool circular = false;

  void Check() const;
};

// Standard deviation of `statistic` over resamples of (values, weights) drawn with replacement:
// the standard error when there are too few estimates for the spread formula to be trusted.
double bootstrap_standard_error(std::span<const double> values, std::span<const double> weights,
                                const WeightedStatistic& statistic,
                                const BootstrapOptions& options = {});

}  // namespace x2car
