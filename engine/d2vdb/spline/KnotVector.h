// The knot vector of a B-spline: its degree and non-decreasing knots.
#pragma once

#include <vector>

#include "d2vdb/spline/ParameterInterval.h"

namespace d2vdb {

/// Highest B-spline degree d2vdb supports (curves and both surface directions). Evaluation uses
/// fixed-size stack buffers of this size, so no evaluation allocates heap memory.
inline constexpr int kMaxSplineDegree = 15;

/// Knots t_0 <= ... <= t_{m-1} of a degree-p B-spline with n = m - p - 1 basis functions
/// N_{0,p} ... N_{n-1,p}. The domain is [t_p, t_n]; the spline is evaluated only there.
///
/// Invariants (checked by the constructor, which throws InputError naming the offending knot):
///   - 1 <= p <= kMaxSplineDegree;
///   - every knot is finite and knots are non-decreasing;
///   - at least 2 (p + 1) knots (n >= p + 1 basis functions);
///   - a non-empty domain, t_p < t_n;
///   - a knot value strictly inside the domain occurs at most p times, so every spline on the knot
///     vector is at least C^0 (d2vdb curves and surfaces are connected); a value at or beyond the
///     domain ends (clamped ends, or the outer knots of unclamped and periodic vectors) occurs at
///     most p + 1 times.
/// Immutable value type; all members are thread-safe.
class KnotVector {
 public:
  /// Validates and stores `knots` for `degree`. Throws InputError when an invariant fails.
  KnotVector(int degree, std::vector<double> knots);

  /// Clamped (open) knot vector for `controlPointCount` control points: p + 1 knots at
  /// domain.start, controlPointCount - p - 1 equally spaced interior knots, p + 1 knots at
  /// domain.end. The curve interpolates its first and last control points. Requires
  /// controlPointCount >= degree + 1 and domain.start < domain.end (else InputError).
  static KnotVector clamped(int degree, int controlPointCount, ParameterInterval domain = {});

  /// Uniform unclamped knot vector: controlPointCount + degree + 1 equally spaced knots, placed so
  /// that the domain [t_p, t_n] is `domain`. Requirements as for clamped().
  static KnotVector uniform(int degree, int controlPointCount, ParameterInterval domain = {});

  /// Uniform periodic knot vector of a closed spline with `uniqueControlPointCount` = n distinct
  /// control points: n + 2p + 1 equally spaced knots, domain [t_p, t_{n+p}] = `domain` split into n
  /// spans, for the n + p wrapped control points P_0..P_{n-1}, P_0..P_{p-1}. Requires
  /// n >= degree + 1 and a non-empty domain (else InputError).
  static KnotVector periodic(int degree, int uniqueControlPointCount,
                             ParameterInterval domain = {});

  /// The degree p.
  int degree() const noexcept { return degree_; }
  /// All knots t_0..t_{m-1}.
  const std::vector<double>& values() const noexcept { return knots_; }
  /// Knot t_index; no bounds check.
  double operator[](int index) const { return knots_[static_cast<std::size_t>(index)]; }
  /// Number of knots m.
  int size() const noexcept { return static_cast<int>(knots_.size()); }
  /// Number of basis functions (control points of an open spline), n = m - p - 1.
  int basisFunctionCount() const noexcept { return size() - degree_ - 1; }
  /// The domain [t_p, t_n].
  ParameterInterval domain() const noexcept {
    return {knots_[degree_], knots_[basisFunctionCount()]};
  }

  /// Index i of the knot span [t_i, t_{i+1}) containing t, with p <= i <= n - 1 and t_i < t_{i+1};
  /// the end of the domain belongs to the last non-empty span. Binary search, O(log m).
  /// Parameters within rounding (16 ulp of the domain's magnitude) outside the domain are treated
  /// as its nearest end; anything else outside, and NaN, throws InputError.
  int findSpan(double t) const;

  /// The number of knots exactly equal to t (0 when t is not a knot).
  int multiplicity(double t) const;

  /// The distinct knot values in the domain, ascending, both ends included: the breakpoints
  /// between the polynomial pieces (and the Bézier segments) of a spline.
  std::vector<double> breakpoints() const;

  /// True when the knot vector is, to within 1e-9 of its domain length per knot, the uniform
  /// periodic vector periodic(p, n - p, domain()) of a closed spline.
  bool isUniformPeriodic() const;

  /// Exact knot-by-knot equality (same degree and bitwise equal knot values).
  bool operator==(const KnotVector& other) const {
    return degree_ == other.degree_ && knots_ == other.knots_;
  }
  bool operator!=(const KnotVector& other) const { return !(*this == other); }

 private:
  int degree_;
  std::vector<double> knots_;
  int lastSpan_;  // the last non-empty span index, returned for t at the end of the domain
};

}  // namespace d2vdb
