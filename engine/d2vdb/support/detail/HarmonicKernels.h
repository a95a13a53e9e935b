// Internal to the support module: block evaluation of the real spherical harmonics and the ladder
// matrices of their partial derivatives (SphericalHarmonics.h states the basis convention).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace d2vdb::detail {

/// Recurrence coefficients of the normalised harmonics, for every degree up to
/// kMaxSupportDegree: with Lambda_l^m such that Y_l^{+-m} = Lambda_l^m(z) (Re, Im)((x + i y)^m)
/// on the unit sphere, Lambda_m^m = sectoral[m] and Lambda_l^m = a[l][m] z Lambda_{l-1}^m -
/// b[l][m] Lambda_{l-2}^m for l >= m + 1 (b = 0 for l = m + 1).
struct RecurrenceTables {
  std::vector<double> sectoral;
  std::vector<std::vector<double>> a;
  std::vector<std::vector<double>> b;
  RecurrenceTables();
};

/// The tables, built once.
const RecurrenceTables& recurrenceTables();

/// Writes Y_j(n_i) for the `count` unit vectors n_i = (x[i], y[i], z[i]) and every harmonic of
/// degree <= `degree` into `out`: out[j * stride + i] (column j holds harmonic j at all points,
/// so the recurrences run vectorised over the points). `degree` must be in 0..kMaxSupportDegree
/// (not checked here). Each point's values depend on that point only (bit for bit).
void evaluateHarmonicBlock(int degree, int count, const double* x, const double* y, const double* z,
                           double* out, int stride);

/// The matrix D of d/dx_axis on coefficient vectors: harmonicPartialDerivative(c, degree, axis)
/// = D c, with harmonicCount(degree - 1) rows and harmonicCount(degree) columns and at most two
/// non-zeros per column.
Eigen::SparseMatrix<double> partialDerivativeMatrix(int degree, int axis);

/// The degree l of the harmonic at coefficient index `index`.
int harmonicDegreeOf(int index);

}  // namespace d2vdb::detail
