// B-spline basis functions N_{i,p} nonzero at a parameter, and their derivatives.
#pragma once

#include <Eigen/Core>

#include "d2vdb/spline/KnotVector.h"

namespace d2vdb {

/// Values of the p + 1 basis functions nonzero on one knot span: entry j is N_{span-p+j,p}(t).
/// Fixed capacity, so returning one never allocates.
using BasisValues =
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxSplineDegree + 1, 1>;

/// Derivatives of the p + 1 basis functions nonzero on one knot span: entry (k, j) is
/// d^k/dt^k N_{span-p+j,p}(t), rows k = 0..maxOrder (row 0 holds the values). Fixed capacity.
using BasisDerivatives = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                       kMaxSplineDegree + 1, kMaxSplineDegree + 1>;

/// The nonzero basis values at t on knot span `span` (as returned by knots.findSpan(t)), by the
/// Cox-de Boor recurrence: non-negative and summing to 1 for t in the span. For t outside the span
/// the span's polynomial pieces are evaluated (extrapolated). O(p^2), no heap allocation.
/// Throws InputError when `span` is not a non-empty span index p <= span < n.
BasisValues basisValues(const KnotVector& knots, int span, double t);

/// The nonzero basis functions at t on knot span `span` and their derivatives of orders
/// 0..maxOrder with respect to t (orders above p are zero). Derivatives are those of the span's
/// polynomial pieces, i.e. one-sided (from the right, or from the left on the last span) at knots.
/// O(p^2 + maxOrder p), no heap allocation. Throws InputError for an invalid span or a maxOrder
/// outside 0..kMaxSplineDegree.
BasisDerivatives basisDerivatives(const KnotVector& knots, int span, double t, int maxOrder);

}  // namespace d2vdb
