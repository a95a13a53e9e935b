// Non-rational tensor-product B-spline surfaces, each direction open or closed (periodic).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/KnotVector.h"
#include "d2vdb/spline/ParameterInterval.h"

namespace d2vdb {

/// Position and first and second partial derivatives at one parameter pair (u, v).
struct SurfaceDerivatives {
  Eigen::Vector3d point;
  Eigen::Vector3d du;
  Eigen::Vector3d dv;
  Eigen::Vector3d duu;
  Eigen::Vector3d duv;
  Eigen::Vector3d dvv;
};

/// A tensor-product B-spline surface S(u, v) = sum_i sum_j N_{i,p}(u) M_{j,q}(v) P_{i,j} in 3D.
///
/// Control grid: countU() x countV() stored points, P_{i,j} at index i * countV() + j (rows over
/// u, v index fastest) - the same nesting as the JSON file, control_points[i][j].
/// Each direction is open (its knot vector has countU() resp. countV() basis functions) or closed:
/// the stored points are the unique ones, the knot vector is the uniform periodic vector with
/// count + 2 degree + 1 knots, and basis index i uses grid row i mod countU() (see
/// controlPointIndex()); the surface is C^(degree-1) across that seam and parameters are reduced
/// modulo the domain length. Open directions reject parameters outside their domain.
///
/// Evaluation: two binary searches plus O(p q + p^2 + q^2), no heap allocation;
/// degrees <= kMaxSplineDegree. All const members are thread-safe.
class BSplineSurface {
 public:
  /// A surface from its knot vectors and control grid (row-major as above). For a closed
  /// direction the knot vector must be uniform periodic (to within 1e-9 of the domain length; it
  /// is replaced by the exact one) with at least degree + 1 unique rows/columns. Throws InputError
  /// for a grid size that does not match the knots, non-periodic closed knots, or a non-finite
  /// control point.
  BSplineSurface(KnotVector knotsU, KnotVector knotsV, std::vector<Eigen::Vector3d> controlPoints,
                 bool closedU = false, bool closedV = false);

  /// Open surface on clamped uniform knot vectors over the given domains; `controlPoints` holds
  /// countU * countV points, row-major as above. InputError as for the constructor.
  static BSplineSurface clamped(int degreeU, int degreeV, int countU, int countV,
                                std::vector<Eigen::Vector3d> controlPoints,
                                ParameterInterval domainU = {}, ParameterInterval domainV = {});

  /// Degree in u (p).
  int degreeU() const { return knotsU_.degree(); }
  /// Degree in v (q).
  int degreeV() const { return knotsV_.degree(); }
  /// Knot vector in u (periodic with countU() + 2p + 1 knots when closed in u).
  const KnotVector& knotsU() const { return knotsU_; }
  /// Knot vector in v.
  const KnotVector& knotsV() const { return knotsV_; }
  /// True when the u direction is periodic.
  bool isClosedU() const { return closedU_; }
  /// True when the v direction is periodic.
  bool isClosedV() const { return closedV_; }
  /// Parameter domain in u.
  ParameterInterval domainU() const { return knotsU_.domain(); }
  /// Parameter domain in v.
  ParameterInterval domainV() const { return knotsV_.domain(); }

  /// Number of stored control point rows (along u).
  int countU() const { return countU_; }
  /// Number of stored control points per row (along v).
  int countV() const { return countV_; }
  /// All stored control points, P_{i,j} at i * countV() + j.
  const std::vector<Eigen::Vector3d>& controlPoints() const { return controlPoints_; }
  /// Stored control point P_{i,j}; no bounds check.
  const Eigen::Vector3d& controlPoint(int i, int j) const {
    return controlPoints_[static_cast<std::size_t>(i * countV_ + j)];
  }
  /// Index into controlPoints() of the point multiplying N_{basisU}(u) M_{basisV}(v), for basis
  /// indices 0 <= basisU < knotsU().basisFunctionCount() (likewise v); wraps closed directions.
  /// Fitting solvers use it to assemble their matrices. No bounds check.
  int controlPointIndex(int basisU, int basisV) const {
    const int i = basisU < countU_ ? basisU : basisU - countU_;
    const int j = basisV < countV_ ? basisV : basisV - countV_;
    return i * countV_ + j;
  }

  /// Replaces the stored control points (same count, finite; InputError leaves the surface
  /// unchanged).
  void setControlPoints(std::vector<Eigen::Vector3d> controlPoints);

  /// S(u, v). InputError for a parameter outside an open direction's domain (beyond rounding) or
  /// a non-finite parameter.
  Eigen::Vector3d evaluate(double u, double v) const;
  /// S(u, v) from the basis functions of knot spans `spanU`, `spanV`; as derivativesInSpans().
  Eigen::Vector3d evaluateInSpans(int spanU, int spanV, double u, double v) const;

  /// S and its partial derivatives Su, Sv, Suu, Suv, Svv at (u, v) (one-sided at knots, from the
  /// right or, at the end of a domain, from the left). Failure behaviour as evaluate().
  SurfaceDerivatives derivatives(double u, double v) const;
  /// The same sums with the basis functions of knot spans `spanU`, `spanV` (indices as
  /// KnotVector::findSpan() gives them), for a caller that keeps to one span: a Bezier patch
  /// evaluated up to its end. The parameters must lie in those spans' closed intervals; nothing is
  /// checked.
  SurfaceDerivatives derivativesInSpans(int spanU, int spanV, double u, double v) const;

  /// samplesU x samplesV points S(u_i, v_j) on the parameter grid u_i = domainU().at(i /
  /// (samplesU - 1)), v_j likewise (both ends included), at index i * samplesV + j.
  /// InputError when either count is below 2.
  std::vector<Eigen::Vector3d> sample(int samplesU, int samplesV) const;

 private:
  KnotVector knotsU_;
  KnotVector knotsV_;
  std::vector<Eigen::Vector3d> controlPoints_;
  int countU_;
  int countV_;
  bool closedU_;
  bool closedV_;
};

}  // namespace d2vdb
