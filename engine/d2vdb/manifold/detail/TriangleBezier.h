// Internal: triangular Bézier patches of low degree (value and derivatives), in barycentric
// coordinates (u, v, w) = (1 - v - w, v, w) with derivatives taken with respect to (v, w).
#pragma once

#include <Eigen/Core>

#include <array>

namespace d2vdb::detail {

/// Index of control point b_{ijk} (i + j + k = n; exponents of u, v, w) in the layout used
/// here: blocks of equal j, k increasing inside a block.
constexpr int triangleIndex(int n, int j, int k) {
  return j * (n + 1) - j * (j - 1) / 2 + k;
}

/// Position and derivatives with respect to (v, w) of a patch point.
struct PatchJet {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dw = Eigen::Vector3d::Zero();
  Eigen::Vector3d dvv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dvw = Eigen::Vector3d::Zero();
  Eigen::Vector3d dww = Eigen::Vector3d::Zero();
};

/// Evaluates the degree-N triangular Bézier patch with (N + 1)(N + 2) / 2 control points at
/// (v, w) by de Casteljau's algorithm; `order` 0, 1 or 2 selects the derivatives computed.
template <int N>
PatchJet evaluateTriangleBezier(const std::array<Eigen::Vector3d, (N + 1) * (N + 2) / 2>& net,
                                double v, double w, int order) {
  static_assert(N >= 2, "degree 2 or more");
  const double u = 1.0 - v - w;
  std::array<Eigen::Vector3d, (N + 1) * (N + 2) / 2> work = net;
  // Reduce to degree 2.
  for (int m = N; m > 2; --m) {
    for (int j = 0; j < m; ++j) {
      for (int k = 0; k < m - j; ++k) {
        work[triangleIndex(m - 1, j, k)] = u * work[triangleIndex(m, j, k)] +
                                           v * work[triangleIndex(m, j + 1, k)] +
                                           w * work[triangleIndex(m, j, k + 1)];
      }
    }
  }
  // Degree 2: q200 q101 q002 / q110 q011 / q020 in the (j, k) layout.
  const Eigen::Vector3d q200 = work[triangleIndex(2, 0, 0)];
  const Eigen::Vector3d q101 = work[triangleIndex(2, 0, 1)];
  const Eigen::Vector3d q002 = work[triangleIndex(2, 0, 2)];
  const Eigen::Vector3d q110 = work[triangleIndex(2, 1, 0)];
  const Eigen::Vector3d q011 = work[triangleIndex(2, 1, 1)];
  const Eigen::Vector3d q020 = work[triangleIndex(2, 2, 0)];
  const Eigen::Vector3d l100 = u * q200 + v * q110 + w * q101;
  const Eigen::Vector3d l010 = u * q110 + v * q020 + w * q011;
  const Eigen::Vector3d l001 = u * q101 + v * q011 + w * q002;
  PatchJet jet;
  jet.position = u * l100 + v * l010 + w * l001;
  if (order >= 1) {
    jet.dv = N * (l010 - l100);
    jet.dw = N * (l001 - l100);
  }
  if (order >= 2) {
    constexpr double kScale = N * (N - 1);
    jet.dvv = kScale * (q020 - 2.0 * q110 + q200);
    jet.dvw = kScale * (q011 - q110 - q101 + q200);
    jet.dww = kScale * (q002 - 2.0 * q101 + q200);
  }
  return jet;
}

/// The position alone, from the Bernstein basis N! / (i! j! k!) u^i v^j w^k directly (cheaper
/// than de Casteljau for one point).
template <int N>
Eigen::Vector3d triangleBezierPosition(
    const std::array<Eigen::Vector3d, (N + 1) * (N + 2) / 2>& net, double v, double w) {
  const double u = 1.0 - v - w;
  double pu[N + 1], pv[N + 1], pw[N + 1];
  pu[0] = pv[0] = pw[0] = 1.0;
  for (int i = 1; i <= N; ++i) {
    pu[i] = pu[i - 1] * u;
    pv[i] = pv[i - 1] * v;
    pw[i] = pw[i - 1] * w;
  }
  // Multinomial coefficients N! / (i! j! k!) from binomials C(N, j) C(N - j, k).
  double binomial[N + 1][N + 1] = {};
  for (int n = 0; n <= N; ++n) {
    binomial[n][0] = binomial[n][n] = 1.0;
    for (int k = 1; k < n; ++k) binomial[n][k] = binomial[n - 1][k - 1] + binomial[n - 1][k];
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int j = 0; j <= N; ++j) {
    for (int k = 0; k <= N - j; ++k) {
      const double weight = binomial[N][j] * binomial[N - j][k] * pu[N - j - k] * pv[j] * pw[k];
      sum += weight * net[triangleIndex(N, j, k)];
    }
  }
  return sum;
}

}  // namespace d2vdb::detail
