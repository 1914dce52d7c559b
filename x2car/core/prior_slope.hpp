// The offset of a series at zero regressor, with a nuisance slope that has a prior: each sample is
//   v_i = offset + slope * x_i + e_i,
// and the slope's prior (a physical gain known to within a range, e.g. a car body's pitch per
// unit of acceleration) makes the fit well posed on drives whose regressor hardly varies (a drive
// that speeds up all along: the slope and the offset cannot be told apart from the data, and the
// prior's spread then goes into the offset's standard error instead of a guess into its value).
//
// The data's own information on the slope counts only as much as the correlated residuals allow:
// the formal least-squares variance is inflated by the ratio of the residuals' moving-block
// variance of the mean to their independent-sample one (core/standard_error.hpp).
#pragma once

#include <span>
#include <vector>

#include "x2car/core/standard_error.hpp"

namespace x2car {

struct SlopePrior {
  double mean = 0.0;                // [value unit / regressor unit]
  double standard_deviation = 0.0;  // [value unit / regressor unit], > 0
  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct OffsetWithSlope {
  double offset = 0.0;                // the value at x = 0
  double slope = 0.0;                 // posterior mean of the slope
  double slope_std = 0.0;             // its posterior standard deviation
  double noise_standard_error = 0.0;  // the residuals' series_standard_error (block, t-corrected)
  // sqrt(noise_standard_error^2 + (mean x * slope_std)^2 + floor^2).
  double standard_error = 0.0;
};

// Fits the samples where `use` is true (times increasing; all spans of one length; at least 2
// used samples, else std::invalid_argument). Gaussian prior on the slope, least squares on the
// data (outliers are the caller's to remove):
//   precision = 1 / prior_sd^2 + Sxx / (s^2 k),   slope = (prior_mean / prior_sd^2 + Sxy / (s^2 k))
//   / precision, offset = mean(v) - slope * mean(x),
// with Sxx, Sxy about the means, s^2 the residuals' variance and k >= 1 their correlation
// inflation. `floor` >= 0 is added in quadrature (a bias no spread shows).
OffsetWithSlope offset_with_prior_slope(std::span<const double> times,
                                        std::span<const double> values,
                                        std::span<const double> regressor,
                                        const std::vector<bool>& use, const SlopePrior& prior,
                                        const MovingBlockOptions& blocks, double floor = 0.0);

}  // namespace x2car
