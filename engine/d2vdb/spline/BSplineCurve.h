// Non-rational B-spline curves in 2D or 3D, open or closed (periodic).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/BezierCurve.h"
#include "d2vdb/spline/KnotVector.h"
#include "d2vdb/spline/ParameterInterval.h"

namespace d2vdb {

/// Position and first and second derivatives (with respect to the curve parameter) at one
/// parameter.
struct CurveDerivatives {
  Eigen::Vector3d point;
  Eigen::Vector3d first;
  Eigen::Vector3d second;
};

/// One polynomial piece of a B-spline curve: `curve` on [0, 1] maps s to the spline's
/// C(interval.at(s)). Derivatives of `curve` are with respect to s, i.e. interval.length() times
/// those with respect to the spline parameter.
struct BezierSegment {
  BezierCurve curve;
  ParameterInterval interval;
};

/// A B-spline curve C(t) = sum_i N_{i,p}(t) P_i on its knot vector's domain.
///
/// Points are Eigen::Vector3d. dimension() is 2 or 3; a 2D curve has z = 0 in every control point
/// (validated), so all downstream code works in 3D.
///
/// Open curves: knots().basisFunctionCount() == controlPointCount(); clamped or unclamped.
/// Closed curves: the n = controlPointCount() unique control points are stored once; the knot
/// vector is the uniform periodic one, KnotVector::periodic(p, n, domain), with n + 2p + 1
/// knots, and basis function i uses control point i mod n (the first p points are wrapped), see
/// controlPointIndex(). A closed curve is C^(p-1) everywhere, across the seam C(start) = C(end)
/// included; parameters outside its domain are reduced modulo the domain length.
///
/// Evaluation costs one binary search plus O(p^2) and allocates nothing; p <= kMaxSplineDegree.
/// All const members are thread-safe.
class BSplineCurve {
 public:
  /// A curve from its knot vector and control points. Open (closed = false): the control point
  /// count must equal knots.basisFunctionCount(). Closed: `controlPoints` are the n unique points
  /// and `knots` must be the uniform periodic vector with n + 2p + 1 knots (to within 1e-9 of the
  /// domain length; it is then replaced by the exact periodic vector on the same domain).
  /// Throws InputError for a wrong count, a non-periodic closed knot vector, a dimension other
  /// than 2 or 3, a non-finite control point, or a 2D control point with z != 0.
  BSplineCurve(KnotVector knots, std::vector<Eigen::Vector3d> controlPoints, int dimension = 3,
               bool closed = false);

  /// Open curve on the clamped uniform knot vector KnotVector::clamped(degree, n, domain): it
  /// starts at the first control point and ends at the last.
  static BSplineCurve clamped(int degree, std::vector<Eigen::Vector3d> controlPoints,
                              int dimension = 3, ParameterInterval domain = {});

  /// Closed curve through the uniform periodic knot vector on `domain` with the given n >=
  /// degree + 1 unique control points.
  static BSplineCurve closed(int degree, std::vector<Eigen::Vector3d> uniqueControlPoints,
                             int dimension = 3, ParameterInterval domain = {});

  /// The degree p.
  int degree() const { return knots_.degree(); }
  /// 2 or 3.
  int dimension() const { return dimension_; }
  /// True for a periodic (closed) representation.
  bool isClosed() const { return closed_; }
  /// The knot vector (for closed curves the full periodic vector, n + 2p + 1 knots).
  const KnotVector& knots() const { return knots_; }
  /// The parameter domain [t_p, t_{basisFunctionCount}].
  ParameterInterval domain() const { return knots_.domain(); }

  /// The stored control points: all of them for open curves, the n unique ones for closed curves.
  const std::vector<Eigen::Vector3d>& controlPoints() const { return controlPoints_; }
  /// controlPoints().size().
  int controlPointCount() const { return static_cast<int>(controlPoints_.size()); }
  /// The stored control point that basis function `basisIndex` (0 <= basisIndex <
  /// knots().basisFunctionCount()) multiplies: basisIndex itself for open curves, basisIndex mod n
  /// for closed ones. Fitting solvers use it to assemble their matrices. No bounds check.
  int controlPointIndex(int basisIndex) const {
    return basisIndex < controlPointCount() ? basisIndex : basisIndex - controlPointCount();
  }

  /// Replaces the stored control points (same count; the validation of the constructor applies,
  /// InputError leaves the curve unchanged). The knot vector stays.
  void setControlPoints(std::vector<Eigen::Vector3d> controlPoints);

  /// C(t). Open curves throw InputError for t outside the domain (beyond rounding) or NaN.
  Eigen::Vector3d evaluate(double t) const;

  /// C(t), C'(t), C''(t). Derivatives at an interior knot are one-sided from the right (from the
  /// left at the end of the domain); they are continuous there unless the knot's multiplicity
  /// reaches p (first derivative) or p - 1 (second). Same failure behaviour as evaluate().
  CurveDerivatives derivatives(double t) const;

  /// The derivative of order `order` (0 = position, up to kMaxSplineDegree; orders above p are
  /// zero) at t. InputError for another order or a bad t.
  Eigen::Vector3d derivative(double t, int order) const;

  /// `count` >= 2 points C(t_i), t_i = domain().at(i / (count - 1)), i = 0..count-1: uniform in
  /// parameter, both ends included (for closed curves the last point equals the first).
  /// InputError for count < 2.
  std::vector<Eigen::Vector3d> sample(int count) const;

  /// Inserts knot t `times` times (Boehm's algorithm); the curve is geometrically and
  /// parametrically unchanged. t must lie in the domain; afterwards its multiplicity may be at most
  /// p strictly inside the domain, p + 1 at the domain ends (else InputError, curve unchanged).
  /// A closed curve is first converted to openRepresentation() (isClosed() becomes false; the
  /// geometry stays closed and periodic in value), because a periodic knot vector cannot stay
  /// uniform under insertion.
  void insertKnot(double t, int times = 1);

  /// The same curve as an open B-spline: for a closed curve the periodic knot vector with the
  /// n + p wrapped control points P_0..P_{n-1}, P_0..P_{p-1} (unclamped); open curves are
  /// returned unchanged.
  BSplineCurve openRepresentation() const;

  /// The polynomial pieces, one Bézier curve of degree p per non-empty knot span in the domain,
  /// in parameter order (by blossoming: control point k of the piece on [a, b] is the blossom
  /// with p - k arguments a and k arguments b). The curve is unchanged: segment(s) =
  /// C(interval.at(s)).
  std::vector<BezierSegment> toBezierSegments() const;

 private:
  // Maps t into the domain: wraps for closed curves, passes t through for open ones.
  double parameterInDomain(double t) const;

  KnotVector knots_;
  std::vector<Eigen::Vector3d> controlPoints_;
  int dimension_;
  bool closed_;
};

}  // namespace d2vdb
