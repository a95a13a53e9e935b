// S(u, v) = |P(u) - Q(v)|^2 of two Bézier curves in tensor-product Bernstein form.
#pragma once

#include <Eigen/Core>

#include "d2vdb/spline/BezierCurve.h"

namespace d2vdb::detail {

/// The squared distance S(u, v) = |P(u) - Q(v)|^2, (u, v) in [0, 1]^2, between a point of the
/// Bézier curve P (degree n) and a point of Q (degree m), written as
/// S(u, v) = sum_{r, k} F_{r, k} B_{r, 2n}(u) B_{k, 2m}(v) (Chen, Ma, Xu and Paul 2010).
/// The coefficients are formed from the differences P_i - Q_j of the control points (no
/// cancellation between large coordinates), so min/max of the coefficients bound S on the unit
/// square to within rounding. Immutable value type; requires 2n, 2m <= kMaxBernsteinDegree.
class SquaredDistanceTensor {
 public:
  /// Coefficients F_{r, k}, rows r = 0..2n (u), columns k = 0..2m (v), fixed capacity.
  using Coefficients = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                     kMaxBernsteinDegree + 1, kMaxBernsteinDegree + 1>;

  /// The tensor of |p(u) - q(v)|^2. Throws InputError when a degree exceeds kMaxSplineDegree.
  SquaredDistanceTensor(const BezierCurve& p, const BezierCurve& q);

  /// 2n.
  int degreeU() const { return static_cast<int>(coefficients_.rows()) - 1; }
  /// 2m.
  int degreeV() const { return static_cast<int>(coefficients_.cols()) - 1; }
  /// All coefficients F_{r, k}.
  const Coefficients& coefficients() const { return coefficients_; }

  /// S(u, v) from the coefficients (Bernstein basis values in u and v).
  double evaluate(double u, double v) const;

  /// Smallest coefficient: min over the unit square of S is at least this.
  double minCoefficient() const { return coefficients_.minCoeff(); }
  /// Largest coefficient: max over the unit square of S is at most this.
  double maxCoefficient() const { return coefficients_.maxCoeff(); }
  /// An absolute bound on the rounding error of each coefficient (a few ulps of the largest
  /// |P_i - Q_j|^2); callers comparing coefficients with thresholds add it as a safety margin.
  double roundingBound() const { return roundingBound_; }

 private:
  Coefficients coefficients_;
  double roundingBound_ = 0.0;
};

}  // namespace d2vdb::detail
