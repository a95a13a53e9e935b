// Test helpers for the spline module: random inputs and references computed independently of the
// library (naive recursions, blossoms from elementary symmetric polynomials).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <random>
#include <vector>

#include "d2vdb/spline/KnotVector.h"

namespace d2vdb::test {

/// Random valid knot vector of `degree`: random distinct interior breakpoints with random
/// multiplicities 1..degree; clamped ends or (when !clamped) distinct unclamped outer knots.
inline KnotVector randomKnotVector(std::mt19937& rng, int degree, bool clamped) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> breakpointCount(0, 5);
  std::uniform_int_distribution<int> multiplicity(1, degree);
  std::vector<double> breaks;
  const int count = breakpointCount(rng);
  for (int i = 0; i < count; ++i) breaks.push_back(-1.0 + 3.0 * unit(rng));
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  const double start = -1.5;
  const double end = 2.5;
  std::vector<double> knots;
  if (clamped) {
    knots.assign(static_cast<std::size_t>(degree + 1), start);
  } else {
    for (int i = degree; i >= 1; --i) knots.push_back(start - i * (0.2 + 0.5 * unit(rng)));
    std::sort(knots.begin(), knots.end());
    knots.push_back(start);
  }
  for (double b : breaks) {
    const int m = multiplicity(rng);
    for (int i = 0; i < m; ++i) knots.push_back(b);
  }
  if (clamped) {
    for (int i = 0; i <= degree; ++i) knots.push_back(end);
  } else {
    knots.push_back(end);
    double t = end;
    for (int i = 0; i < degree; ++i) knots.push_back(t += 0.2 + 0.5 * unit(rng));
  }
  return KnotVector(degree, knots);
}

/// N_{i,p}(t) by the textbook Cox-de Boor recursion with half-open intervals [t_i, t_{i+1}) and
/// 0/0 = 0. Valid for t strictly inside the domain (not at its end).
inline double naiveBasis(const std::vector<double>& knots, int i, int p, double t) {
  if (p == 0) return (knots[i] <= t && t < knots[i + 1]) ? 1.0 : 0.0;
  double value = 0.0;
  const double leftWidth = knots[i + p] - knots[i];
  if (leftWidth > 0.0) value += (t - knots[i]) / leftWidth * naiveBasis(knots, i, p - 1, t);
  const double rightWidth = knots[i + p + 1] - knots[i + 1];
  if (rightWidth > 0.0) {
    value += (knots[i + p + 1] - t) / rightWidth * naiveBasis(knots, i + 1, p - 1, t);
  }
  return value;
}

/// Elementary symmetric polynomials e_0..e_n of the values x_1..x_n.
inline std::vector<double> elementarySymmetric(const std::vector<double>& x) {
  std::vector<double> e(x.size() + 1, 0.0);
  e[0] = 1.0;
  for (std::size_t m = 0; m < x.size(); ++m) {
    for (std::size_t k = m + 1; k >= 1; --k) e[k] += x[m] * e[k - 1];
  }
  return e;
}

/// Binomial coefficient by the multiplicative formula.
inline double binomial(int n, int k) {
  double value = 1.0;
  for (int i = 1; i <= k; ++i) value = value * (n - k + i) / i;
  return value;
}

/// Blossom of the degree-p monomial t^k at (x_1..x_p): e_k(x) / C(p, k).
inline double monomialBlossom(const std::vector<double>& x, int k) {
  return elementarySymmetric(x)[static_cast<std::size_t>(k)] /
         binomial(static_cast<int>(x.size()), k);
}

/// Value of the vector polynomial sum_k coefficients[k] t^k.
inline Eigen::Vector3d polynomialValue(const std::vector<Eigen::Vector3d>& coefficients, double t) {
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  for (std::size_t k = coefficients.size(); k-- > 0;) value = value * t + coefficients[k];
  return value;
}

/// Random points with coordinates in [-2, 2] (z = 0 when planar).
inline std::vector<Eigen::Vector3d> randomPoints(std::mt19937& rng, int count,
                                                 bool planar = false) {
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const double x = coordinate(rng);
    const double y = coordinate(rng);
    const double z = coordinate(rng);
    points.emplace_back(x, y, planar ? 0.0 : z);
  }
  return points;
}

/// A random parameter uniformly in [start, end].
inline double randomParameter(std::mt19937& rng, double start, double end) {
  return std::uniform_real_distribution<double>(start, end)(rng);
}

}  // namespace d2vdb::test
