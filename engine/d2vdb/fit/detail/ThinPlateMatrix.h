// Internal: quadratic smoothing energies of a tensor-product B-spline surface as matrices over its
// control points: the thin-plate (bending) energy and the membrane (stretching) energy.
#pragma once

#include <Eigen/Sparse>

#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// The thin-plate energy matrix T of the surface over the normalised parameters
/// (s, t) = ((u - u_start) / L_u, (v - v_start) / L_v) in [0, 1]^2:
///   int_0^1 int_0^1 (|x_ss|^2 + 2 |x_st|^2 + |x_tt|^2) ds dt = sum_a P_a^T T P_a
/// over the coordinates a, indexed by stored control point (closed directions wrap through
/// controlPointIndex, so the wrapped basis functions add up). The normalised parameters make the
/// energy independent of the knot domains. Computed cell by cell by Gauss-Legendre quadrature with
/// (p + 1) x (q + 1) points, which is exact for these polynomial integrands. Symmetric positive
/// semidefinite; its null space holds the affine maps of the parameters (x = A (s, t) + b) when
/// both degrees are at least 2. Never throws for a valid surface.
Eigen::SparseMatrix<double> thinPlateMatrix(const BSplineSurface& surface);

/// The membrane energy matrix M over the same normalised parameters:
///   int_0^1 int_0^1 (|x_s|^2 + |x_t|^2) ds dt = sum_a P_a^T M P_a.
/// Exact Gauss-Legendre quadrature as thinPlateMatrix(). Symmetric positive semidefinite.
Eigen::SparseMatrix<double> membraneMatrix(const BSplineSurface& surface);

}  // namespace d2vdb::detail
