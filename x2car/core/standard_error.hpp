// Standard errors that hold for correlated samples (issue 12, DESIGN §6 "uncertainty is a
// promise"), for any calibrator that averages per-sample or per-frame values over a drive:
//   - the moving-block estimate: samples close in time share their errors (the same stretch of
//     road, the same GNSS multipath, the same body lean), so the spread of means over blocks
//     longer than that correlation time measures what the average is worth, not the count of
//     samples;
//   - a small-sample (Student-t) factor, since a spread from a few blocks or segments is itself
//     uncertain and a plain one would be too small as often as not;
//   - never below the formal per-sample standard error (independent samples);
//   - a floor, added in quadrature, for errors the data cannot show: a bias of the device that is
//     constant over the drive (a GNSS/INS heading bias), a road that leans one way all drive.
// The coverage checks (bench/*_coverage.cpp) measure that |error| <= 2 SE in >= 90 % of simulated
// runs with these figures.
#pragma once

#include <span>

namespace x2car {

// t_{0.975, dof} / z_{0.975}: the factor that turns a standard error estimated with `dof` degrees
// of freedom into one whose +-1.96 interval keeps its 95 % (1 for dof -> infinity, 6.5 for
// dof = 1). dof > 0, fractional values allowed (interpolated). Throws std::invalid_argument
// otherwise.
double small_sample_factor(double degrees_of_freedom);

struct MovingBlockOptions {
  // Block length [s]: longer than the correlation time of the errors (GNSS multipath and the
  // atmosphere drift over ~10 s; a road's grade and crossfall change over ~100 m).
  double block_s = 10.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct MovingBlockStandardError {
  double standard_error = 0.0;  // of the mean, before any small-sample factor [value's unit]
  // Approximate degrees of freedom of that estimate, 1.5 (n/L - 1) (overlapping batch means); 0
  // when the samples do not span two blocks.
  double degrees_of_freedom = 0.0;
  double block_samples = 0.0;  // L, samples per block
};

// Standard error of the mean of `values` sampled at `times` [s] (increasing; gaps allowed), by the
// moving-block bootstrap over time (Künsch 1989), computed exactly instead of by resampling: the
// variance of the means of all overlapping blocks of L samples (L = the samples in block_s at the
// series' mean rate), scaled to the whole series and corrected for the estimated mean
// (overlapping batch means, Meketon & Schmeiser 1984):
//   Var(mean) = L / ((n - L + 1)(n - L)) * sum_j (mean_j - mean)^2.
// For independent samples this is s^2 / n on average. A series shorter than two blocks is cut
// into two (L = n / 2, 1.5 degrees of freedom): it cannot show its correlation over more than half
// its length. With fewer than 4 samples the result is the independent-sample s / sqrt(n) with
// degrees_of_freedom 0. Needs 2 values or more.
MovingBlockStandardError moving_block_standard_error(std::span<const double> times,
                                                     std::span<const double> values,
                                                     const MovingBlockOptions& options = {});

// The standard error of the mean of a time series of per-sample or per-frame values, the one call
// a calibrator needs (the camera's per-frame angles as much as the GNSS/INS samples):
//   block    the moving-block estimate, times small_sample_factor(its degrees of freedom);
//   formal   s / sqrt(n), the samples taken as independent;
//   combined sqrt(max(block, formal)^2 + floor^2).
struct SeriesStandardError {
  double block = 0.0;
  double formal = 0.0;
  double combined = 0.0;
};
// Needs 2 values or more (as moving_block_standard_error); `floor` >= 0 in the values' unit.
SeriesStandardError series_standard_error(std::span<const double> times,
                                          std::span<const double> values,
                                          const MovingBlockOptions& options = {},
                                          double floor = 0.0);

// The standard error of an estimate from its parts: the largest of the data-driven ones (each
// already corrected for its sample size), with the bias floor added in quadrature:
//   SE = sqrt(max(parts)^2 + floor^2).
double combined_standard_error(std::span<const double> data_standard_errors, double floor = 0.0);

}  // namespace x2car
