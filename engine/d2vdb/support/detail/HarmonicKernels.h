// Internal to the support module: block evaluation of the real spherical harmonics and the ladder
// matrices of their partial derivatives (SphericalHarmonics.h states the basis convention).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace d2vdb::detail {

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
