#include "x2car/core/pspline.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "x2car/core/band_matrix.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car {
namespace {

using detail::band_pattern;
using detail::BandLdlt;
using detail::difference_penalty;
using detail::SparseMatrix;
using detail::SymmetricBand;
using detail::trace_of_inverse_times;

constexpr int kMaxDegree = 5;
// Guards memory against a span / knot spacing that cannot be meant (e.g. times in ns).
constexpr double kMaxIntervals = 1e7;
constexpr double kGcvGridStep = 0.5;    // coarse GCV grid step [decades of lambda]
constexpr double kGcvTolerance = 0.01;  // golden-section stopping width [decades]
constexpr double kGoldenRatio = 0.6180339887498949;

// Values of the degree + 1 uniform B-splines that are nonzero on one knot interval, at local
// position u in [0, 1]: Cox-de Boor recursion (Piegl & Tiller, The NURBS Book, A2.2). On uniform
// knots the denominators left + right of the recursion are all equal to the current degree q.
void uniform_bspline_basis(double u, int degree, double* basis) {
  basis[0] = 1.0;
  for (int q = 1; q <= degree; ++q) {
    double saved = 0.0;
    for (int r = 0; r < q; ++r) {
      const double temp = basis[r] / q;
      basis[r] = saved + (r + 1 - u) * temp;  // right[r + 1] = r + 1 - u
      saved = (u + q - r - 1) * temp;         // left[q - r] = u + q - r - 1
    }
    basis[q] = saved;
  }
}

// Validates the input; returns the number of samples with positive weight.
int check_samples(std::span<const double> times, std::span<const std::span<const double>> series,
                  std::span<const double> weights, int min_samples) {
  if (series.empty()) reject_argument("P-spline: no series to fit");
  for (std::size_t s = 0; s < series.size(); ++s) {
    if (series[s].size() != times.size()) {
      reject_argument("P-spline: series {} has {} values for {} times", s, series[s].size(),
                      times.size());
    }
  }
  if (!weights.empty() && weights.size() != times.size()) {
    reject_argument("P-spline: {} weights for {} times", weights.size(), times.size());
  }
  int positive = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) reject_argument("P-spline: time {} is not finite", k);
    if (k > 0 && !(times[k] > times[k - 1])) {
      reject_argument("P-spline: times must be strictly increasing (sample {}: {} after {})", k,
                      times[k], times[k - 1]);
    }
    for (std::size_t s = 0; s < series.size(); ++s) {
      if (!std::isfinite(series[s][k]))
        reject_argument("P-spline: value {} of series {} is not finite", k, s);
    }
    const double weight = weights.empty() ? 1.0 : weights[k];
    if (!std::isfinite(weight) || weight < 0.0) {
      reject_argument("P-spline: weight {} is {} (must be finite and >= 0)", k, weight);
    }
    if (weight > 0.0) ++positive;
  }
  if (positive < min_samples) {
    reject_argument("P-spline: {} samples with positive weight, need at least {}", positive,
                    min_samples);
  }
  return positive;
}

}  // namespace

void PSplineOptions::Check() const {
  const OptionsCheck check("PSplineOptions");
  check.in_range("degree", degree, 3, kMaxDegree);
  check.in_range("penalty_order", penalty_order, 1, degree);
  check.positive("knot_spacing_s", knot_spacing_s);
  if (smoothing) check.positive("smoothing", *smoothing);
  check.ordered("gcv_log10_min", gcv_log10_min, "gcv_log10_max", gcv_log10_max);
  check.that(gcv_log10_min < gcv_log10_max, "gcv_log10_min", "must be < gcv_log10_max",
             gcv_log10_min);
}

double PSpline::value(double t) const { return derivative(t, 0); }

double PSpline::derivative(double t, int order) const {
  if (order < 0 || order > 2) reject_argument("PSpline: derivative order {} not in 0..2", order);
  if (std::isnan(t)) return std::numeric_limits<double>::quiet_NaN();
  const double x = (std::clamp(t, start_time_, end_time_) - start_time_) / knot_spacing_;
  const int interval = std::clamp(int(std::floor(x)), 0, intervals_ - 1);
  double basis[kMaxDegree + 1];
  uniform_bspline_basis(x - interval, degree_ - order, basis);
  const std::vector<double>& coefficients = coefficients_[order];
  double sum = 0.0;
  for (int a = 0; a <= degree_ - order; ++a) sum += coefficients[interval + a] * basis[a];
  return sum;
}

// Everything that does not depend on lambda, computed once; evaluate() then costs one banded
// factorisation, one Takahashi pass and one solve + residual pass per series.
class PSplineFitter {
 public:
  PSplineFitter(std::span<const double> times, std::span<const std::span<const double>> series,
                std::span<const double> weights, const PSplineOptions& options);

  std::vector<PSpline> fit() const;

 private:
  struct Evaluation {
    double lambda = 0.0;
    double score = std::numeric_limits<double>::infinity();  // GCV(lambda)
    double effective_dof = 0.0;
    std::vector<double> rss;                    // per series
    std::vector<Eigen::VectorXd> coefficients;  // per series
  };

  void build_design();
  void accumulate_normal_equations();
  Evaluation evaluate(double lambda) const;
  double residual_sum_of_squares(std::size_t series, const Eigen::VectorXd& coefficients) const;
  // lambda = 10^x * (mean diagonal of B'WB): GCV's search variable (see PSplineOptions).
  Evaluation evaluate_relative(double x) const {
    return evaluate(mean_diagonal_ * std::pow(10, x));
  }
  Evaluation minimise_gcv() const;
  Evaluation golden_section(double a, double b) const;
  PSpline make_spline(const Evaluation& evaluation, std::size_t series) const;

  std::span<const double> times_;
  std::span<const std::span<const double>> series_;
  std::vector<double> weights_;  // w_k, all 1 when none were given
  PSplineOptions options_;
  int degree_ = 3;
  double knot_spacing_ = 1.0;  // h [s]
  int intervals_ = 1;
  int size_ = 0;                              // number of coefficients m = intervals + degree
  double samples_ = 0.0;                      // n: samples with positive weight
  double mean_diagonal_ = 0.0;                // tr(B'WB) / m
  std::vector<int> first_basis_;              // per sample: index of its first nonzero B-spline
  std::vector<double> basis_;                 // per sample: degree + 1 B-spline values
  SymmetricBand gram_{0, 0};                  // B'WB
  SymmetricBand penalty_{0, 0};               // D'D
  SparseMatrix pattern_;                      // band pattern of B'WB + lambda D'D
  std::vector<double> offsets_;               // weighted mean per series, subtracted from y
  std::vector<Eigen::VectorXd> right_sides_;  // B'W(y - offset) per series
};

PSplineFitter::PSplineFitter(std::span<const double> times,
                             std::span<const std::span<const double>> series,
                             std::span<const double> weights, const PSplineOptions& options)
    : times_(times), series_(series), options_(options) {
  options_.Check();
  degree_ = options_.degree;
  samples_ = check_samples(times, series, weights, degree_ + 2);
  weights_.assign(weights.begin(), weights.end());
  if (weights.empty()) weights_.assign(times.size(), 1.0);
  const double span = times.back() - times.front();
  const double intervals = std::ceil(span / options_.knot_spacing_s * (1.0 - 1e-12));
  if (intervals > kMaxIntervals) {
    reject_argument("P-spline: time span {} s / knot spacing {} s needs {} knot intervals (max {})",
                    span, options_.knot_spacing_s, intervals, kMaxIntervals);
  }
  intervals_ = std::max(1, int(intervals));
  knot_spacing_ = span / intervals_;
  size_ = intervals_ + degree_;
  build_design();
  accumulate_normal_equations();
  penalty_ = difference_penalty(size_, options_.penalty_order, degree_);
  pattern_ = band_pattern(size_, degree_);
  for (int i = 0; i < size_; ++i) mean_diagonal_ += gram_.at(i, i) / size_;
}

void PSplineFitter::build_design() {
  const int width = degree_ + 1;
  first_basis_.resize(times_.size());
  basis_.resize(times_.size() * width);
  for (std::size_t k = 0; k < times_.size(); ++k) {
    const double x = (times_[k] - times_.front()) / knot_spacing_;
    const int interval = std::clamp(int(std::floor(x)), 0, intervals_ - 1);
    first_basis_[k] = interval;
    uniform_bspline_basis(x - interval, degree_, &basis_[k * width]);
  }
}

// Centring each series first keeps the coefficients small for tracks far from their origin,
// which matters for heavy smoothing where the system is ill-conditioned; constants are
// reproduced exactly and not penalised, so the fit is unchanged.
void PSplineFitter::accumulate_normal_equations() {
  const int width = degree_ + 1;
  offsets_.assign(series_.size(), 0.0);
  double weight_sum = 0.0;
  for (const double w : weights_) weight_sum += w;
  for (std::size_t s = 0; s < series_.size(); ++s) {
    for (std::size_t k = 0; k < times_.size(); ++k) offsets_[s] += weights_[k] * series_[s][k];
    offsets_[s] /= weight_sum;
  }
  gram_ = SymmetricBand(size_, degree_);
  right_sides_.assign(series_.size(), Eigen::VectorXd::Zero(size_));
  for (std::size_t k = 0; k < times_.size(); ++k) {
    const double* basis = &basis_[k * width];
    const int first = first_basis_[k];
    const double w = weights_[k];
    for (int a = 0; a < width; ++a) {
      for (int b = a; b < width; ++b) gram_.at(first + b, first + a) += w * basis[a] * basis[b];
      for (std::size_t s = 0; s < series_.size(); ++s) {
        right_sides_[s][first + a] += w * basis[a] * (series_[s][k] - offsets_[s]);
      }
    }
  }
}

double PSplineFitter::residual_sum_of_squares(std::size_t series,
                                              const Eigen::VectorXd& coefficients) const {
  const std::span<const double> values = series_[series];
  const int width = degree_ + 1;
  double rss = 0.0;
  for (std::size_t k = 0; k < times_.size(); ++k) {
    const double* basis = &basis_[k * width];
    double fitted = 0.0;
    for (int a = 0; a < width; ++a) fitted += basis[a] * coefficients[first_basis_[k] + a];
    const double residual = values[k] - offsets_[series] - fitted;
    rss += weights_[k] * residual * residual;
  }
  return rss;
}

// Solves (B'WB + lambda D'D) c = B'Wy for every series and scores lambda by GCV (E&M eq. 13),
// summed over the series that share it.
PSplineFitter::Evaluation PSplineFitter::evaluate(double lambda) const {
  Evaluation evaluation;
  evaluation.lambda = lambda;
  SparseMatrix system = pattern_;
  double* values = system.valuePtr();
  for (int col = 0; col < size_; ++col) {
    const int begin = system.outerIndexPtr()[col];
    for (int row = col; row <= std::min(col + degree_, size_ - 1); ++row) {
      values[begin + row - col] = gram_.at(row, col) + lambda * penalty_.at(row, col);
    }
  }
  BandLdlt ldlt;
  ldlt.compute(system);
  if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() <= 0.0).any()) return evaluation;
  evaluation.effective_dof = trace_of_inverse_times(ldlt, gram_);
  double rss_sum = 0.0;
  for (std::size_t s = 0; s < series_.size(); ++s) {
    evaluation.coefficients.push_back(ldlt.solve(right_sides_[s]));
    evaluation.rss.push_back(residual_sum_of_squares(s, evaluation.coefficients.back()));
    rss_sum += evaluation.rss.back();
  }
  const double residual_dof = samples_ - evaluation.effective_dof;
  if (residual_dof > 1e-9 * samples_) {
    evaluation.score = samples_ * rss_sum / (residual_dof * residual_dof);
  }
  return evaluation;
}

// Coarse grid over log10(lambda / mean diagonal of B'WB) (GCV can have several local minima),
// then golden-section search in the grid cells beside the best grid point.
PSplineFitter::Evaluation PSplineFitter::minimise_gcv() const {
  const double low = options_.gcv_log10_min;
  const double high = options_.gcv_log10_max;
  const int steps = std::max(2, int(std::ceil((high - low) / kGcvGridStep)));
  const double step = (high - low) / steps;
  Evaluation best;
  double best_x = low;
  for (int i = 0; i <= steps; ++i) {
    Evaluation candidate = evaluate_relative(low + i * step);
    if (candidate.score < best.score) {
      best = std::move(candidate);
      best_x = low + i * step;
    }
  }
  if (!std::isfinite(best.score))
    reject_argument("P-spline: no smoothing parameter gives a well-posed fit");
  Evaluation refined = golden_section(std::max(low, best_x - step), std::min(high, best_x + step));
  return refined.score < best.score ? std::move(refined) : std::move(best);
}

// Golden-section search for the minimum of GCV over log10 relative lambda in [a, b].
PSplineFitter::Evaluation PSplineFitter::golden_section(double a, double b) const {
  double x1 = b - kGoldenRatio * (b - a);
  double x2 = a + kGoldenRatio * (b - a);
  Evaluation e1 = evaluate_relative(x1);
  Evaluation e2 = evaluate_relative(x2);
  while (b - a > kGcvTolerance) {
    if (e1.score <= e2.score) {  // the minimum lies in [a, x2]
      b = x2;
      x2 = x1;
      e2 = std::move(e1);
      x1 = b - kGoldenRatio * (b - a);
      e1 = evaluate_relative(x1);
    } else {  // the minimum lies in [x1, b]
      a = x1;
      x1 = x2;
      e1 = std::move(e2);
      x2 = a + kGoldenRatio * (b - a);
      e2 = evaluate_relative(x2);
    }
  }
  return e1.score <= e2.score ? std::move(e1) : std::move(e2);
}

PSpline PSplineFitter::make_spline(const Evaluation& evaluation, std::size_t series) const {
  PSpline spline;
  spline.degree_ = degree_;
  spline.start_time_ = times_.front();
  spline.end_time_ = times_.back();
  spline.knot_spacing_ = knot_spacing_;
  spline.intervals_ = intervals_;
  const Eigen::VectorXd& c = evaluation.coefficients[series];
  spline.coefficients_[0].assign(c.data(), c.data() + c.size());
  for (double& coefficient : spline.coefficients_[0]) coefficient += offsets_[series];
  for (int order = 1; order <= 2; ++order) {  // derivative of a B-spline (de Boor 1978, X(12))
    const std::vector<double>& previous = spline.coefficients_[order - 1];
    std::vector<double>& next = spline.coefficients_[order];
    next.resize(previous.size() - 1);
    for (std::size_t i = 0; i < next.size(); ++i) {
      next[i] = (previous[i + 1] - previous[i]) / knot_spacing_;
    }
  }
  spline.smoothing_ = evaluation.lambda;
  spline.effective_dof_ = evaluation.effective_dof;
  const double residual_dof = std::max(samples_ - evaluation.effective_dof, 1e-9 * samples_);
  spline.residual_std_ = std::sqrt(evaluation.rss[series] / residual_dof);
  return spline;
}

std::vector<PSpline> PSplineFitter::fit() const {
  Evaluation evaluation;
  if (options_.smoothing) {
    evaluation = evaluate(*options_.smoothing);
    if (evaluation.coefficients.empty()) {
      reject_argument(
          "P-spline: the system is singular for smoothing {} (too few distinct samples?)",
          *options_.smoothing);
    }
  } else {
    evaluation = minimise_gcv();
  }
  std::vector<PSpline> splines;
  for (std::size_t s = 0; s < series_.size(); ++s) splines.push_back(make_spline(evaluation, s));
  return splines;
}

PSpline fit_pspline(std::span<const double> times, std::span<const double> values,
                    const PSplineOptions& options, std::span<const double> weights) {
  const std::span<const double> series[1] = {values};
  return PSplineFitter(times, series, weights, options).fit().front();
}

std::vector<PSpline> fit_psplines_shared(std::span<const double> times,
                                         std::span<const std::span<const double>> series,
                                         const PSplineOptions& options,
                                         std::span<const double> weights) {
  return PSplineFitter(times, series, weights, options).fit();
}

}  // namespace x2car
