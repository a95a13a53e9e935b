// Bézier curves in 3D (2D curves carry z = 0): control points in Bernstein form on [0, 1].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <utility>
#include <vector>

#include "d2vdb/spline/Bernstein.h"

namespace d2vdb {

/// The polynomial curve C(t) = sum_i P_i B_{i,n}(t), t in [0, 1], of degree
/// n <= kMaxBernsteinDegree. Control points live in fixed-capacity storage: copying, evaluating
/// and subdividing never allocate. Immutable value type.
class BezierCurve {
 public:
  /// Control points as the columns of a 3 x (n + 1) matrix of fixed capacity.
  using ControlPoints =
      Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, kMaxBernsteinDegree + 1>;

  /// From 1 to kMaxBernsteinDegree + 1 finite control points; throws InputError otherwise.
  explicit BezierCurve(const std::vector<Eigen::Vector3d>& controlPoints);
  /// Same, from the columns of a matrix.
  explicit BezierCurve(const ControlPoints& controlPoints);

  /// The degree n.
  int degree() const { return static_cast<int>(controlPoints_.cols()) - 1; }
  /// n + 1.
  int controlPointCount() const { return static_cast<int>(controlPoints_.cols()); }
  /// Control point P_index; no bounds check.
  Eigen::Vector3d controlPoint(int index) const { return controlPoints_.col(index); }
  /// All control points (columns).
  const ControlPoints& controlPoints() const { return controlPoints_; }

  /// C(t) by de Casteljau's algorithm (O(n^2); t outside [0, 1] extrapolates).
  Eigen::Vector3d evaluate(double t) const;

  /// The hodograph C'(t) with respect to t: degree n - 1, control points n (P_{i+1} - P_i); a
  /// single zero point when n = 0.
  BezierCurve derivative() const;

  /// Splits at t: C on [0, t] and C on [t, 1], each reparameterised to [0, 1].
  std::pair<BezierCurve, BezierCurve> subdivide(double t) const;

  /// C on [a, b] reparameterised to [0, 1], D(s) = C(a + s (b - a)); throws InputError when
  /// a == b or either is not finite.
  BezierCurve restricted(double a, double b) const;

  /// The same curve written with degree n + times (throws InputError above kMaxBernsteinDegree).
  BezierCurve elevated(int times = 1) const;

  /// The curve moved by `offset` (C(t) + offset); e.g. translated(-p) gives C - p.
  BezierCurve translated(const Eigen::Vector3d& offset) const;

  /// One coordinate (axis 0, 1 or 2) as a scalar Bernstein polynomial; InputError for other axes.
  BernsteinPolynomial coordinate(int axis) const;

  /// The axis-aligned box of the control points, which contains C([0, 1]) (convex hull property).
  Eigen::AlignedBox3d controlPointBounds() const;

 private:
  struct Unchecked {};
  BezierCurve(Unchecked, const ControlPoints& controlPoints) : controlPoints_(controlPoints) {}

  ControlPoints controlPoints_;
};

/// The scalar polynomial A(t) . B(t) in Bernstein form, degree n_A + n_B; e.g.
/// dot(C.translated(-p), C.derivative()) is the projection condition (C - p) . C' of a point p onto
/// C. Throws InputError when the degree would exceed kMaxBernsteinDegree.
BernsteinPolynomial dot(const BezierCurve& a, const BezierCurve& b);

}  // namespace d2vdb
