// The coverage check of a calibrator's standard errors (issue 12, DESIGN §6 "uncertainty is a
// promise"): over many simulated runs with known truth, |error| <= 2 SE in at least 90 % of them,
// and the SE no more than 3x the typical |error| (an SE that always covers because it is huge is
// no use either). Each x2car_*_coverage program feeds its runs here and exits non-zero when the
// check fails; `make coverage` runs them all.
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "x2car/core/robust_stats.hpp"

namespace x2car::bench {

// One calibration run against the truth, in the unit of the figure (deg for angles, m for z).
struct CoverageRun {
  std::string label;  // e.g. "urban 20 s seed 7 rtk"
  double error = 0.0;
  double standard_error = 0.0;
};

struct CoverageCriteria {
  double k_sigma = 2.0;            // a run is covered when |error| <= k_sigma * SE
  double min_fraction = 0.90;      // of the runs
  double max_se_over_error = 3.0;  // median SE / median |error|
  int min_runs = 50;
};

struct CoverageSummary {
  int runs = 0;
  int covered = 0;
  double fraction = 0.0;
  double median_abs_error = 0.0;
  double median_standard_error = 0.0;
  double se_over_error = 0.0;  // median SE / median |error|
  bool passes = false;
  std::string verdict;  // what failed, or "ok"
};

inline CoverageSummary summarise_coverage(std::span<const CoverageRun> runs,
                                          const CoverageCriteria& criteria = {}) {
  CoverageSummary summary;
  summary.runs = static_cast<int>(runs.size());
  std::vector<double> errors, standard_errors;
  for (const CoverageRun& run : runs) {
    if (std::abs(run.error) <= criteria.k_sigma * run.standard_error) ++summary.covered;
    errors.push_back(std::abs(run.error));
    standard_errors.push_back(run.standard_error);
  }
  if (summary.runs == 0) {
    summary.verdict = "no runs";
    return summary;
  }
  summary.fraction = static_cast<double>(summary.covered) / summary.runs;
  summary.median_abs_error = median(errors);
  summary.median_standard_error = median(standard_errors);
  summary.se_over_error = summary.median_abs_error > 0.0
                              ? summary.median_standard_error / summary.median_abs_error
                              : INFINITY;
  std::vector<std::string> failures;
  if (summary.runs < criteria.min_runs) {
    failures.push_back(fmt::format("only {} runs (< {})", summary.runs, criteria.min_runs));
  }
  if (summary.fraction < criteria.min_fraction) {
    failures.push_back(fmt::format("{:.0f} % within {:g} SE (< {:.0f} %)", 100.0 * summary.fraction,
                                   criteria.k_sigma, 100.0 * criteria.min_fraction));
  }
  if (summary.se_over_error > criteria.max_se_over_error) {
    failures.push_back(fmt::format("median SE {:.3g} x the median |error| (> {:g})",
                                   summary.se_over_error, criteria.max_se_over_error));
  }
  summary.passes = failures.empty();
  summary.verdict = failures.empty() ? "ok" : fmt::format("{}", fmt::join(failures, "; "));
  return summary;
}

// Prints the runs and the summary; returns the exit code of a coverage program (0 when it passes).
inline int report_coverage(const std::string& what, std::span<const CoverageRun> runs,
                           const CoverageCriteria& criteria = {}) {
  for (const CoverageRun& run : runs) {
    fmt::print("  {:<40} error {:+10.5f}  SE {:9.5f}  {}\n", run.label, run.error,
               run.standard_error,
               std::abs(run.error) <= criteria.k_sigma * run.standard_error ? "" : "NOT COVERED");
  }
  const CoverageSummary summary = summarise_coverage(runs, criteria);
  fmt::print(
      "{}: {} runs, {} within {:g} SE ({:.1f} %), median |error| {:.4g}, median SE {:.4g} "
      "(SE/|error| {:.2f}): {}\n",
      what, summary.runs, summary.covered, criteria.k_sigma, 100.0 * summary.fraction,
      summary.median_abs_error, summary.median_standard_error, summary.se_over_error,
      summary.verdict);
  std::fflush(stdout);
  return summary.passes ? 0 : 1;
}

}  // namespace x2car::bench
