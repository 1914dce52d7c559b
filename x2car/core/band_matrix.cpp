#include "x2car/core/band_matrix.hpp"

#include <algorithm>
#include <stdexcept>

namespace x2car::detail {

// Row r of D holds (-1)^(d-a) binom(d, a) at column r + a.
SymmetricBand difference_penalty(int size, int order, int width) {
  std::vector<double> row(order + 1);
  row[0] = 1.0;
  for (int q = 1; q <= order; ++q) {  // coefficients of (x - 1)^q by repeated differencing
    for (int a = q; a >= 1; --a) row[a] = row[a - 1] - row[a];
    row[0] = -row[0];
  }
  SymmetricBand penalty(size, width);
  for (int r = 0; r + order < size; ++r) {
    for (int a = 0; a <= order; ++a) {
      for (int b = a; b <= order; ++b) penalty.at(r + b, r + a) += row[a] * row[b];
    }
  }
  return penalty;
}

SparseMatrix band_pattern(int size, int width) {
  SparseMatrix matrix(size, size);
  matrix.reserve(Eigen::VectorXi::Constant(size, width + 1));
  for (int col = 0; col < size; ++col) {
    for (int row = col; row <= std::min(col + width, size - 1); ++row) matrix.insert(row, col) = 0;
  }
  matrix.makeCompressed();
  return matrix;
}

// Takahashi recursion (Takahashi, Fagan & Chen 1973; Hutchinson & de Hoog 1985):
// Z = D^-1 L^-1 + (I - L')Z gives, for i from the last row up and j > i within the band,
//   Z_ji = -sum_{k>i} L_ki Z_kj,   Z_ii = 1/D_i - sum_{k>i} L_ki Z_ki.
double trace_of_inverse_times(const BandLdlt& ldlt, const SymmetricBand& gram) {
  const int m = gram.size;
  const int w = gram.width;
  SymmetricBand lower(m, w);  // unit lower factor L below its diagonal
  const SparseMatrix& factor = ldlt.matrixL().nestedExpression();
  for (int col = 0; col < m; ++col) {
    for (SparseMatrix::InnerIterator it(factor, col); it; ++it) {
      if (it.row() == col) continue;
      if (it.row() > col + w) throw std::logic_error("P-spline: LDL' factor left the band");
      lower.at(int(it.row()), col) = it.value();
    }
  }
  const Eigen::VectorXd& d = ldlt.vectorD();
  SymmetricBand inverse(m, w);
  for (int i = m - 1; i >= 0; --i) {
    const int last = std::min(i + w, m - 1);
    for (int j = last; j > i; --j) {
      double sum = 0.0;
      for (int k = i + 1; k <= last; ++k) {
        sum += lower.at(k, i) * inverse.at(std::max(k, j), std::min(k, j));
      }
      inverse.at(j, i) = -sum;
    }
    double sum = 0.0;
    for (int k = i + 1; k <= last; ++k) sum += lower.at(k, i) * inverse.at(k, i);
    inverse.at(i, i) = 1.0 / d[i] - sum;
  }
  double trace = 0.0;
  for (int col = 0; col < m; ++col) {
    trace += inverse.at(col, col) * gram.at(col, col);
    for (int row = col + 1; row <= std::min(col + w, m - 1); ++row) {
      trace += 2.0 * inverse.at(row, col) * gram.at(row, col);
    }
  }
  return trace;
}

}  // namespace x2car::detail
