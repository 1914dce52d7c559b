#include "x2car/core/band_matrix.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace x2car::detail {
namespace {

Eigen::MatrixXd dense(const SymmetricBand& band) {
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(band.size, band.size);
  for (int col = 0; col < band.size; ++col) {
    for (int row = col; row <= std::min(col + band.width, band.size - 1); ++row) {
      matrix(row, col) = matrix(col, row) = band.at(row, col);
    }
  }
  return matrix;
}

// D with rows (-1)^(d-a) binom(d, a) at columns r + a, written out for d = 1, 2, 3.
Eigen::MatrixXd difference_matrix(int size, int order) {
  const std::vector<std::vector<double>> rows{{-1, 1}, {1, -2, 1}, {-1, 3, -3, 1}};
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(size - order, size);
  for (int r = 0; r + order < size; ++r) {
    for (int a = 0; a <= order; ++a) d(r, r + a) = rows[order - 1][a];
  }
  return d;
}

TEST(DifferencePenalty, IsDTransposeDOfTheDifferenceMatrix) {
  for (int order = 1; order <= 3; ++order) {
    const Eigen::MatrixXd d = difference_matrix(9, order);
    const Eigen::MatrixXd expected = d.transpose() * d;
    EXPECT_LE((dense(difference_penalty(9, order, 3)) - expected).cwiseAbs().maxCoeff(), 1e-12)
        << "order " << order;
  }
}

TEST(TraceOfInverseTimes, MatchesTheDenseInverse) {
  // A = G + lambda D'D, as in the P-spline fit; G a banded Gram-like matrix.
  const int size = 12;
  const int width = 3;
  SymmetricBand gram(size, width);
  for (int col = 0; col < size; ++col) {
    for (int row = col; row <= std::min(col + width, size - 1); ++row) {
      gram.at(row, col) = row == col ? 2.0 + 0.1 * col : 0.3 / (1 + row - col) - 0.01 * col;
    }
  }
  const SymmetricBand penalty = difference_penalty(size, 3, width);
  SparseMatrix system = band_pattern(size, width);
  for (int col = 0; col < size; ++col) {
    for (int row = col; row <= std::min(col + width, size - 1); ++row) {
      system.coeffRef(row, col) = gram.at(row, col) + 0.5 * penalty.at(row, col);
    }
  }
  BandLdlt ldlt;
  ldlt.compute(system);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::MatrixXd a = dense(gram) + 0.5 * dense(penalty);
  const double expected = (a.inverse() * dense(gram)).trace();
  EXPECT_NEAR(trace_of_inverse_times(ldlt, gram), expected, 1e-10 * std::abs(expected));
}

}  // namespace
}  // namespace x2car::detail
