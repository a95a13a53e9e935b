// Real spherical harmonics in Cartesian form: the basis of d2vdb's support functions.
#pragma once

#include <Eigen/Core>

#include <vector>

// Basis convention
// ================
// Y_l^m, l = 0..L, m = -l..l, orthonormal on the unit sphere S^2 (integral of Y^2 over S^2 = 1),
// without the Condon-Shortley phase:
//   m > 0:  Y_l^m  = sqrt(2) N_lm P_l^m(z) cos(m phi) = c_lm Lambda_l^m(z) Re((x + i y)^m)
//   m = 0:  Y_l^0  =         N_l0 P_l(z)
//   m < 0:  Y_l^m  = sqrt(2) N_l|m| P_l^|m|(z) sin(|m| phi) = c_l|m| Lambda_l^|m|(z) Im((x+iy)^|m|)
// with N_lm = sqrt((2l + 1) (l - m)! / (4 pi (l + m)!)) and P_l^m(z) = (1 - z^2)^(m/2) d^m/dz^m
// P_l(z). Written as r^l Y_l^m(x / r), each Y_l^m is a harmonic polynomial, homogeneous of degree
// l in (x, y, z); this polynomial (a "solid harmonic") is the extension off the sphere that d2vdb
// differentiates, so nothing is ever expressed in polar angles and there are no pole
// singularities. The values are computed by the usual three-term recurrence in l for fixed m
// (normalised, hence stable to high degree) and complex powers (x + i y)^m.
// Y_0^0 = 1 / sqrt(4 pi); Y_1^{-1}, Y_1^0, Y_1^1 = sqrt(3 / (4 pi)) (y, z, x).
// Coefficient vectors are ordered by harmonicIndex(l, m) = l^2 + l + m, so the harmonics of degree
// <= L - 1 are a prefix of those of degree <= L.

namespace d2vdb {

/// Highest degree d2vdb's support functions accept. At this degree a coefficient vector has 4225
/// entries and the normal matrix of a fit takes 143 MB.
inline constexpr int kMaxSupportDegree = 64;

/// Number of real spherical harmonics of degree <= `degree`: (degree + 1)^2 (0 for degree < 0).
constexpr int harmonicCount(int degree) {
  return degree < 0 ? 0 : (degree + 1) * (degree + 1);
}

/// Position of Y_l^m in a coefficient vector: l^2 + l + m, for |m| <= l.
constexpr int harmonicIndex(int l, int m) {
  return l * l + l + m;
}

/// The values Y_j(n) of all harmonics of degree <= `degree` at the unit vector `unitNormal`
/// (harmonicCount(degree) values, ordered by harmonicIndex). `unitNormal` is used as given: the
/// result is the solid harmonics r^l Y_l^m evaluated with r^2 taken as 1, so pass a unit vector.
/// Throws InputError for a degree outside 0..kMaxSupportDegree.
Eigen::VectorXd evaluateHarmonics(int degree, const Eigen::Vector3d& unitNormal);

/// Coefficients of the partial derivative d/dx_axis (axis 0, 1, 2 = x, y, z) of the polynomial
/// sum_j coefficients_j r^l_j Y_j (each harmonic extended as its solid harmonic): a polynomial
/// whose terms are again solid harmonics, of one degree less, so the result has
/// harmonicCount(degree - 1) entries (none for degree 0). Exact ladder relations of the solid
/// harmonics (no quadrature). Throws InputError for a coefficient vector whose size is not
/// harmonicCount(degree) or a degree outside 0..kMaxSupportDegree.
Eigen::VectorXd harmonicPartialDerivative(const Eigen::VectorXd& coefficients, int degree,
                                          int axis);

}  // namespace d2vdb
