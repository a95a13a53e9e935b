// Internal: algorithms on control values in Bernstein form, shared by scalar polynomials (one row)
// and Bézier curves (three rows). Columns are the control values b_0..b_n.
#pragma once

#include <Eigen/Core>

#include <array>

#include "d2vdb/spline/Bernstein.h"

namespace d2vdb::detail {

/// Control values of a polynomial in Bernstein form with `Rows` components.
template <int Rows>
using BernsteinControls =
    Eigen::Matrix<double, Rows, Eigen::Dynamic, Rows == 1 ? Eigen::RowMajor : Eigen::ColMajor, Rows,
                  kMaxBernsteinDegree + 1>;

/// Binomial coefficients C(n, k) for 0 <= k <= n <= kMaxBernsteinDegree, exact in double.
struct BinomialTable {
  std::array<std::array<double, kMaxBernsteinDegree + 1>, kMaxBernsteinDegree + 1> value{};
};

constexpr BinomialTable makeBinomialTable() {
  BinomialTable table;
  for (int n = 0; n <= kMaxBernsteinDegree; ++n) {
    for (int k = 0; k <= n; ++k) {
      table.value[n][k] =
          (k == 0 || k == n) ? 1.0 : table.value[n - 1][k - 1] + table.value[n - 1][k];
    }
  }
  return table;
}

inline constexpr BinomialTable kBinomials = makeBinomialTable();

/// The polynomial's value at t by de Casteljau's algorithm.
template <int Rows>
Eigen::Matrix<double, Rows, 1> deCasteljauEvaluate(const BernsteinControls<Rows>& controls,
                                                   double t) {
  BernsteinControls<Rows> work = controls;
  const int n = static_cast<int>(controls.cols()) - 1;
  for (int level = 1; level <= n; ++level) {
    for (int i = 0; i <= n - level; ++i)
      work.col(i) = (1.0 - t) * work.col(i) + t * work.col(i + 1);
  }
  return work.col(0);
}

/// The control values of the pieces on [0, t] and [t, 1], each reparameterised to [0, 1]: the
/// left and right edges of the de Casteljau triangle.
template <int Rows>
void deCasteljauSplit(const BernsteinControls<Rows>& controls, double t,
                      BernsteinControls<Rows>& left, BernsteinControls<Rows>& right) {
  const int n = static_cast<int>(controls.cols()) - 1;
  BernsteinControls<Rows> work = controls;
  left.resize(Rows, n + 1);
  right.resize(Rows, n + 1);
  left.col(0) = work.col(0);
  right.col(n) = work.col(n);
  for (int level = 1; level <= n; ++level) {
    for (int i = 0; i <= n - level; ++i)
      work.col(i) = (1.0 - t) * work.col(i) + t * work.col(i + 1);
    left.col(level) = work.col(0);
    right.col(n - level) = work.col(n - level);
  }
}

/// The blossom f(x_1, ..., x_n) where the first `countA` arguments are a and the rest b:
/// de Casteljau with the parameter of each level taken from the argument list.
template <int Rows>
Eigen::Matrix<double, Rows, 1> blossom(const BernsteinControls<Rows>& controls, int countA,
                                       double a, double b) {
  BernsteinControls<Rows> work = controls;
  const int n = static_cast<int>(controls.cols()) - 1;
  for (int level = 1; level <= n; ++level) {
    const double x = level <= countA ? a : b;
    for (int i = 0; i <= n - level; ++i)
      work.col(i) = (1.0 - x) * work.col(i) + x * work.col(i + 1);
  }
  return work.col(0);
}

/// Control values of f restricted to [a, b] and reparameterised to [0, 1]: the k-th is the
/// blossom with n - k arguments a and k arguments b.
template <int Rows>
BernsteinControls<Rows> restrictTo(const BernsteinControls<Rows>& controls, double a, double b) {
  const int n = static_cast<int>(controls.cols()) - 1;
  BernsteinControls<Rows> result(Rows, n + 1);
  for (int k = 0; k <= n; ++k) result.col(k) = blossom<Rows>(controls, n - k, a, b);
  return result;
}

/// Control values of df/dt: n (b_{i+1} - b_i), degree n - 1; a single zero for n = 0.
template <int Rows>
BernsteinControls<Rows> differentiate(const BernsteinControls<Rows>& controls) {
  const int n = static_cast<int>(controls.cols()) - 1;
  if (n == 0) return BernsteinControls<Rows>::Zero(Rows, 1);
  BernsteinControls<Rows> result(Rows, n);
  for (int i = 0; i < n; ++i) result.col(i) = n * (controls.col(i + 1) - controls.col(i));
  return result;
}

/// Control values of the same polynomial at degree n + 1:
/// b'_i = i / (n + 1) b_{i-1} + (1 - i / (n + 1)) b_i. The caller checks n + 1 <= the maximum.
template <int Rows>
BernsteinControls<Rows> elevateOnce(const BernsteinControls<Rows>& controls) {
  const int n = static_cast<int>(controls.cols()) - 1;
  BernsteinControls<Rows> result(Rows, n + 2);
  result.col(0) = controls.col(0);
  result.col(n + 1) = controls.col(n);
  for (int i = 1; i <= n; ++i) {
    const double weight = static_cast<double>(i) / static_cast<double>(n + 1);
    result.col(i) = weight * controls.col(i - 1) + (1.0 - weight) * controls.col(i);
  }
  return result;
}

/// Coefficients of the scalar product f . g of two polynomials of degrees m and n:
/// c_k = sum_{i+j=k} C(m,i) C(n,j) / C(m+n,k) f_i . g_j. The caller checks m + n <= the maximum.
template <int Rows>
BernsteinControls<1> productCoefficients(const BernsteinControls<Rows>& f,
                                         const BernsteinControls<Rows>& g) {
  const int m = static_cast<int>(f.cols()) - 1;
  const int n = static_cast<int>(g.cols()) - 1;
  BernsteinControls<1> result = BernsteinControls<1>::Zero(1, m + n + 1);
  for (int i = 0; i <= m; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double weight =
          kBinomials.value[m][i] * kBinomials.value[n][j] / kBinomials.value[m + n][i + j];
      result[i + j] += weight * f.col(i).dot(g.col(j));
    }
  }
  return result;
}

}  // namespace d2vdb::detail
