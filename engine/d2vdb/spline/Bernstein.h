// Bernstein basis polynomials and scalar polynomials in Bernstein (Bézier) form on [0, 1].
#pragma once

#include <Eigen/Core>

#include <initializer_list>
#include <utility>
#include <vector>

#include "d2vdb/spline/KnotVector.h"

namespace d2vdb {

/// Highest degree of a Bernstein polynomial or Bézier curve. 2 kMaxSplineDegree + 1 = 31, enough
/// for products such as |C1(u) - C2(v)|^2 and (C(t) - p) . C'(t) of degree-15 curves. Storage
/// is fixed-size, so no Bernstein or Bézier operation allocates heap memory.
inline constexpr int kMaxBernsteinDegree = 2 * kMaxSplineDegree + 1;

/// The Bernstein basis polynomial B_{index,degree}(t) = C(degree, index) t^index (1 - t)^(degree
/// - index). Throws InputError unless 0 <= index <= degree <= kMaxBernsteinDegree.
double bernsteinBasis(int degree, int index, double t);

/// All degree + 1 Bernstein basis values of `degree` at t (entry i is B_{i,degree}(t)).
using BernsteinBasisValues =
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxBernsteinDegree + 1, 1>;

/// Computes all Bernstein basis values of `degree` at t by the triangular recurrence
/// B_{i,d+1} = (1 - t) B_{i,d} + t B_{i-1,d} (stable, no binomials; partition of unity for any t).
/// Throws InputError unless 0 <= degree <= kMaxBernsteinDegree.
BernsteinBasisValues bernsteinBasisValues(int degree, double t);

/// A scalar polynomial f(t) = sum_i c_i B_{i,n}(t) of degree n <= kMaxBernsteinDegree in Bernstein
/// form on [0, 1]. Convex-hull property: min_i c_i <= f(t) <= max_i c_i on [0, 1], which is what
/// root isolation and Hausdorff pruning use. Immutable value type, no heap storage.
class BernsteinPolynomial {
 public:
  /// Coefficients c_0..c_n as a row vector of fixed capacity kMaxBernsteinDegree + 1.
  using Coefficients =
      Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxBernsteinDegree + 1>;

  /// From 1 to kMaxBernsteinDegree + 1 finite coefficients c_0..c_n; throws InputError otherwise.
  explicit BernsteinPolynomial(const Coefficients& coefficients);
  /// Same, from a list of coefficients.
  explicit BernsteinPolynomial(std::initializer_list<double> coefficients);
  /// Same, from a vector of coefficients.
  explicit BernsteinPolynomial(const std::vector<double>& coefficients);

  /// The constant `value` written with `degree` + 1 equal coefficients.
  static BernsteinPolynomial constant(double value, int degree = 0);

  /// The degree n (number of coefficients - 1).
  int degree() const { return static_cast<int>(coefficients_.cols()) - 1; }
  /// The coefficients c_0..c_n.
  const Coefficients& coefficients() const { return coefficients_; }
  /// Coefficient c_index; no bounds check.
  double coefficient(int index) const { return coefficients_[index]; }

  /// f(t) by de Casteljau's algorithm (O(n^2), stable on [0, 1]; other t extrapolate).
  double evaluate(double t) const;

  /// Splits at t: the first polynomial is f on [0, t], the second f on [t, 1], each
  /// reparameterised to [0, 1] (the two halves of one de Casteljau pass).
  std::pair<BernsteinPolynomial, BernsteinPolynomial> subdivide(double t) const;

  /// f on [a, b] reparameterised to [0, 1], g(s) = f(a + s (b - a)), via blossoming; any a != b
  /// (throws InputError when a == b or either is not finite).
  BernsteinPolynomial restricted(double a, double b) const;

  /// df/dt (the hodograph), degree n - 1; the zero constant when n = 0.
  BernsteinPolynomial derivative() const;

  /// The same polynomial written with degree n + times. Throws InputError when times < 0 or the
  /// result would exceed kMaxBernsteinDegree.
  BernsteinPolynomial elevated(int times = 1) const;

  /// Smallest coefficient: a lower bound of f on [0, 1], attained at t = 0 or 1 when it is c_0 or
  /// c_n.
  double minCoefficient() const { return coefficients_.minCoeff(); }
  /// Largest coefficient: an upper bound of f on [0, 1].
  double maxCoefficient() const { return coefficients_.maxCoeff(); }

  /// The product f g, degree n + m (throws InputError above kMaxBernsteinDegree).
  friend BernsteinPolynomial operator*(const BernsteinPolynomial& f, const BernsteinPolynomial& g);
  /// The sum f + g (the lower degree operand is degree-elevated first).
  friend BernsteinPolynomial operator+(const BernsteinPolynomial& f, const BernsteinPolynomial& g);
  /// The difference f - g (the lower degree operand is degree-elevated first).
  friend BernsteinPolynomial operator-(const BernsteinPolynomial& f, const BernsteinPolynomial& g);
  /// The scaled polynomial s f.
  friend BernsteinPolynomial operator*(double s, const BernsteinPolynomial& f);

 private:
  struct Unchecked {};
  BernsteinPolynomial(Unchecked, const Coefficients& coefficients) : coefficients_(coefficients) {}

  Coefficients coefficients_;
};

}  // namespace d2vdb
