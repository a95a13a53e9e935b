// Internal: quadratic smoothing energies of a B-spline curve as matrices over its control points.
#pragma once

#include <Eigen/Sparse>

#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb::detail {

/// The Gram matrix G of the `derivativeOrder`-th derivatives of the curve's basis functions over
/// the normalised parameter u = (t - t_start) / (t_end - t_start) in [0, 1]:
///   G_ij = int_0^1 N_i^(r)(u) N_j^(r)(u) du,
/// indexed by stored control point (closed curves wrap through controlPointIndex, so the wrapped
/// functions add up). Then int |x^(r)(u)|^2 du = sum_a P_a^T G P_a over the coordinates a. The
/// normalised parameter makes the energy independent of the knot domain: for a circle of radius R,
/// int |x''|^2 du = 16 pi^4 R^2 whatever the domain. Computed by Gauss-Legendre quadrature with
/// p + 1 points per knot span (exact for these polynomial integrands). Symmetric positive
/// semidefinite. InputError for derivativeOrder outside 1..p.
Eigen::SparseMatrix<double> derivativeGramMatrix(const BSplineCurve& curve, int derivativeOrder);

/// Gauss-Legendre nodes and weights on [0, 1] with `count` points (1..64), exact for polynomials
/// of degree 2 count - 1. InputError for another count.
void gaussLegendre(int count, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace d2vdb::detail
