// Penalised B-spline (P-spline) smoother of a scalar function of time (Eilers & Marx 1996,
// "Flexible smoothing with B-splines and penalties", Statist. Sci. 11(2)).
//
// The smooth is s(t) = sum_i c_i B_i(t) on uniform knots; the coefficients minimise
//   sum_k w_k (y_k - s(t_k))^2 + lambda * ||D_d c||^2                                   (E&M eq. 5)
// where D_d takes d-th order differences of neighbouring coefficients. lambda is fixed by the
// caller or chosen by generalised cross-validation (Craven & Wahba 1979)
//   GCV(lambda) = n * RSS / (n - tr H)^2,   H = B (B'WB + lambda D'D)^-1 B'W.       (E&M eq. 13)
// Samples may be irregular and have gaps; the penalty bridges the gaps with a polynomial of
// degree d - 1. Several series that share the times (x and y of a track) can share one lambda.
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace x2car {

struct PSplineOptions {
  // Degree of the B-splines, 3..5. Cubic splines have continuous second derivatives, which is all
  // curvature needs.
  int degree = 3;
  // Order d of the coefficient differences penalised, 1..degree. With d = 3 the penalty's null
  // space (what any lambda leaves untouched) is the quadratics: heavy smoothing tends to constant
  // acceleration, so the curvature of a turn is kept, while d = 2 would shrink every turn towards a
  // straight line and bias curvature low (and d = 1 towards standstill, biasing speed).
  int penalty_order = 3;
  // Requested knot spacing [s]. Knots are uniform over [t_first, t_last]; the spacing used is the
  // largest one <= this that divides the span evenly. 0.5 s resolves a car's turns (yaw
  // rates change over seconds) while keeping ~120 coefficients per minute of data.
  double knot_spacing_s = 0.5;
  // lambda of the penalty, > 0, in the units of the objective above (it scales with the weights and
  // the sample rate). nullopt: choose lambda by GCV.
  std::optional<double> smoothing;
  // GCV search range in log10(lambda / s), where s = tr(B'WB) / (number of coefficients) is the
  // mean diagonal of the data term; this relative scale makes the range independent of the sample
  // rate, the weights' scale and the knot spacing. -4 is close to interpolation; +8 with d = 3 is
  // a smoothing window of ~20 knot intervals (lambda ~ window^(2d)).
  double gcv_log10_min = -4.0;
  double gcv_log10_max = 8.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// A fitted spline: a small value type with the coefficients and the fit's diagnostics, made only
// by the fit functions below. Times
// outside [start_time(), end_time()] are clamped to the span: value and derivatives there are those
// at the nearest end (no polynomial extrapolation, which would diverge).
class PSpline {
 public:
  // Value s(t) at time t [s], in the unit of the fitted samples.
  double value(double t) const;
  // d^order s / dt^order at time t [unit / s^order]; order is 0, 1 or 2 (throws otherwise). A NaN
  // time gives NaN.
  double derivative(double t, int order) const;

  double start_time() const { return start_time_; }  // first sample time [s]
  double end_time() const { return end_time_; }      // last sample time [s]
  bool contains(double t) const { return t >= start_time_ && t <= end_time_; }
  int degree() const { return degree_; }
  double knot_spacing() const { return knot_spacing_; }  // knot spacing used [s]
  const std::vector<double>& coefficients() const { return coefficients_[0]; }

  double smoothing() const { return smoothing_; }  // lambda used
  // Effective degrees of freedom tr H: between penalty_order (lambda -> inf) and the number of
  // coefficients (lambda -> 0).
  double effective_dof() const { return effective_dof_; }
  // sqrt(sum w_k r_k^2 / (n - tr H)), the residual standard deviation [unit of samples; with
  // weights 1/sigma_k^2 it is dimensionless and near 1 when the sigmas are right].
  double residual_std() const { return residual_std_; }

 private:
  friend class PSplineFitter;
  PSpline() = default;

  int degree_ = 3;
  double start_time_ = 0.0;    // t_first [s], the first knot
  double end_time_ = 0.0;      // t_last [s], the last knot
  double knot_spacing_ = 1.0;  // h [s]
  int intervals_ = 1;          // number of knot intervals in the span
  // coefficients_[r]: coefficients of the r-th derivative, a spline of degree - r
  // (c^(r)_i = (c^(r-1)_{i+1} - c^(r-1)_i) / h on uniform knots, de Boor 1978, ch. X).
  std::vector<double> coefficients_[3];
  double smoothing_ = 0.0;
  double effective_dof_ = 0.0;
  double residual_std_ = 0.0;
};

// Fits one series y(t). `times` [s] must be finite and strictly increasing, `values` finite and of
// the same length; `weights` empty (all 1) or one finite weight >= 0 per sample. Needs at least
// degree + 2 samples with positive weight. Throws std::invalid_argument on bad input or options.
PSpline fit_pspline(std::span<const double> times, std::span<const double> values,
                    const PSplineOptions& options, std::span<const double> weights = {});

// Fits several series sharing `times` and weights with one lambda. With GCV, lambda minimises the
// summed criterion n * sum_s RSS_s / (n - tr H)^2; one factorisation per lambda serves all series.
// Returns one spline per series, in order.
std::vector<PSpline> fit_psplines_shared(std::span<const double> times,
                                         std::span<const std::span<const double>> series,
                                         const PSplineOptions& options,
                                         std::span<const double> weights = {});

}  // namespace x2car
