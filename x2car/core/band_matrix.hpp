// Symmetric band matrices for the P-spline smoother (pspline.cpp), internal to core: the band
// storage, the difference penalty D'D, the sparse pattern Eigen's LDL' factorises, and the trace
// tr(A^-1 G) that GCV needs, from the band of A^-1 only (Takahashi recursion).
#pragma once

#include <Eigen/SparseCholesky>
#include <cstddef>
#include <vector>

namespace x2car::detail {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
// NaturalOrdering keeps the band: the LDL' factor of a banded matrix has no fill outside it.
using BandLdlt = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>>;

// Symmetric band matrix, lower part stored column by column: (row, col), col <= row <= col + width.
struct SymmetricBand {
  int size = 0;
  int width = 0;
  std::vector<double> values;

  SymmetricBand(int n, int w) : size(n), width(w), values(std::size_t(n) * (w + 1), 0.0) {}
  double& at(int row, int col) { return values[std::size_t(col) * (width + 1) + (row - col)]; }
  double at(int row, int col) const { return values[std::size_t(col) * (width + 1) + (row - col)]; }
};

// d-th order difference penalty D'D (Eilers & Marx 1996, eq. 5) on `size` coefficients, stored
// with band width `width` >= order.
SymmetricBand difference_penalty(int size, int order, int width);

// Sparse lower-triangular band pattern, values set later (per lambda in the P-spline fit). Entry
// (col, k) of the band sits at valuePtr()[outerIndexPtr()[col] + k].
SparseMatrix band_pattern(int size, int width);

// tr(A^-1 G) for A = L D L' (factorised by `ldlt`, with the band width of `gram`) and symmetric G,
// from the entries of A^-1 inside the band only. Cost O(m * width^2); a dense inverse would be
// O(m^3). Throws std::logic_error when the factor has entries outside the band.
double trace_of_inverse_times(const BandLdlt& ldlt, const SymmetricBand& gram);

}  // namespace x2car::detail
