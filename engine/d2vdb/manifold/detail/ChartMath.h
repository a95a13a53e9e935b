// Internal: the maps between a face's canonical equilateral triangle and a vertex chart, in
// plain doubles and in derivative jets.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <vector>

#include "d2vdb/core/MathConstants.h"
#include "d2vdb/manifold/detail/Jet.h"

namespace d2vdb::detail {

/// cos(pi / 6) = sqrt(3) / 2: the chart radius of a degree-6 vertex and the height of the
/// canonical unit triangle.
inline constexpr double kCos30 = 0.86602540378443864676;

/// The canonical point z = b[next] + b[after] exp(i pi / 3) of corner `corner`.
inline Eigen::Vector2d canonicalPoint(const Eigen::Vector3d& bary, int corner) {
  const double bNext = bary[(corner + 1) % 3];
  const double bAfter = bary[(corner + 2) % 3];
  return {bNext + 0.5 * bAfter, kCos30 * bAfter};
}

/// Barycentric coordinates (b_corner, b_next, b_after) of the canonical point z of a corner.
inline Eigen::Vector3d cornerBary(const Eigen::Vector2d& z) {
  const double bAfter = z.y() / kCos30;
  const double bNext = z.x() - 0.5 * bAfter;
  return {1.0 - bNext - bAfter, bNext, bAfter};
}

/// |p| / divisor for a point p = (x, y) as an order-3 jet in the coordinates (x, y) themselves, in
/// closed form: r_x = x / r, r_xx = y^2 / r^3, r_xy = -x y / r^3, r_yy = x^2 / r^3,
/// r_xxx = -3 x y^2 / r^5, r_xxy = y (2 x^2 - y^2) / r^5, r_xyy = x (2 y^2 - x^2) / r^5,
/// r_yyy = -3 x^2 y / r^5 (r = |p|), each divided by `divisor`. p must not be 0.
inline Jet<3> radiusJetOfVariables(double x, double y, double divisor = 1.0) {
  const double rr = x * x + y * y;
  const double length = std::sqrt(rr);
  const double inv = 1.0 / (divisor * length);
  const double inv3 = inv / rr;
  const double inv5 = inv3 / rr;
  Jet<3> r;
  r.v = length / divisor;
  r.d[0] = x * inv;
  r.d[1] = y * inv;
  r.h[0] = y * y * inv3;
  r.h[1] = -x * y * inv3;
  r.h[2] = x * x * inv3;
  r.t[0] = -3.0 * x * y * y * inv5;
  r.t[1] = y * (2.0 * x * x - y * y) * inv5;
  r.t[2] = x * (2.0 * y * y - x * x) * inv5;
  r.t[3] = -3.0 * x * x * y * inv5;
  return r;
}

/// The polar radius r = |p| and angle of a point p = (x, y) as order-3 jets in the coordinates
/// (x, y) themselves, in closed form (the angle's value is set to 0: only its derivatives are
/// meaningful). p must not be 0.
inline void polarJetsOfVariables(double x, double y, Jet<3>& r, Jet<3>& angle) {
  r = radiusJetOfVariables(x, y);
  const double rr = x * x + y * y;
  // The angle (as in polarAngle): a_x = -y / r^2, a_y = x / r^2, a_xx = 2 x y / r^4,
  // a_xy = (y^2 - x^2) / r^4, a_yy = -a_xx, a_xxx = 2 y (y^2 - 3 x^2) / r^6 = -a_xyy,
  // a_xxy = 2 x (x^2 - 3 y^2) / r^6 = -a_yyy.
  const double inv2 = 1.0 / rr;
  const double inv4 = inv2 * inv2;
  const double inv6 = inv4 * inv2;
  angle.v = 0.0;
  angle.d[0] = -y * inv2;
  angle.d[1] = x * inv2;
  angle.h[0] = 2.0 * x * y * inv4;
  angle.h[1] = (y * y - x * x) * inv4;
  angle.h[2] = -angle.h[0];
  angle.t[0] = 2.0 * y * (y * y - 3.0 * x * x) * inv6;
  angle.t[1] = 2.0 * x * (x * x - 3.0 * y * y) * inv6;
  angle.t[2] = -angle.t[0];
  angle.t[3] = -angle.t[1];
}

/// Constants of the polar map of a vertex of degree n.
struct PolarMap {
  double angleScale;   ///< 6 / n: chart angle per canonical angle
  double radiusScale;  ///< cos(pi / n) / cos(pi / 6): chart radius per canonical radius
  double sector;       ///< 2 pi / n
  double chartRadius;  ///< cos(pi / n)

  bool rotation;  ///< degree 6: the map is the rotation by 2 pi k / 6 (radiusScale 1)

  explicit PolarMap(int degree)
      : angleScale(6.0 / degree),
        radiusScale(degree == 6 ? 1.0 : std::cos(kPi / degree) / kCos30),
        sector(2.0 * kPi / degree),
        chartRadius(degree == 6 ? kCos30 : std::cos(kPi / degree)),
        rotation(degree == 6) {}

  /// cos and sin of 2 pi k / 6, exactly rounded.
  static void sixth(int k, double& c, double& s) {
    static constexpr double kCos[6] = {1.0, 0.5, -0.5, -1.0, -0.5, 0.5};
    static constexpr double kSin[6] = {0.0, kCos30, kCos30, 0.0, -kCos30, -kCos30};
    c = kCos[k % 6];
    s = kSin[k % 6];
  }

  /// The chart point of canonical point z of sector k.
  Eigen::Vector2d toChart(const Eigen::Vector2d& z, int k) const {
    if (rotation) {
      double c, s;
      sixth(k, c, s);
      return {c * z.x() - s * z.y(), s * z.x() + c * z.y()};
    }
    const double r = z.norm();
    const double angle = std::atan2(z.y(), z.x()) * angleScale + sector * k;
    const double rho = r * radiusScale;
    return {rho * std::cos(angle), rho * std::sin(angle)};
  }

  /// The sector k (0..n-1) of chart point p and its canonical point there. A point on a sector
  /// boundary belongs to the sector counter-clockwise from it.
  Eigen::Vector2d toCanonical(const Eigen::Vector2d& p, int degree, int& k) const {
    if (rotation) {
      // Degree 6: the sector from the signs of p across the rays at multiples of 60 degrees (a
      // point on ray j lies in sector j, the centre in sector 0), then the inverse rotation.
      const double x = p.x(), y = p.y();
      if (x == 0.0 && y == 0.0) {
        k = 0;
      } else if (y > 0.0 || (y == 0.0 && x > 0.0)) {
        // Sectors 0..2: across the rays at 60 and 120 degrees.
        k = 0.5 * y - kCos30 * x < 0.0 ? 0 : (-0.5 * y - kCos30 * x < 0.0 ? 1 : 2);
      } else {
        // Sectors 3..5: across the rays at 240 and 300 degrees.
        k = kCos30 * x - 0.5 * y < 0.0 ? 3 : (kCos30 * x + 0.5 * y < 0.0 ? 4 : 5);
      }
      double c, s;
      sixth(k, c, s);
      return {c * x + s * y, c * y - s * x};
    }
    double beta = std::atan2(p.y(), p.x());
    if (beta < 0.0) beta += 2.0 * kPi;
    k = static_cast<int>(std::floor(beta / sector));
    if (k >= degree) k = degree - 1;
    if (k < 0) k = 0;
    const double alpha = (beta - sector * k) / angleScale;
    const double r = p.norm() / radiusScale;
    return {r * std::cos(alpha), r * std::sin(alpha)};
  }

  /// The chart point of a canonical point given as jets (z must not be 0 when Order > 0 and the
  /// degree is not 6; the map is not differentiable at the centre then).
  template <int Order>
  void toChart(const Jet<Order>& zx, const Jet<Order>& zy, int k, Jet<Order>& px,
               Jet<Order>& py) const {
    if (rotation) {
      double c, s;
      sixth(k, c, s);
      px = c * zx - s * zy;
      py = s * zx + c * zy;
      return;
    }
    const Jet<Order> r = sqrt(zx * zx + zy * zy);
    Jet<Order> angle = angleScale * atan2(zy, zx);
    angle.v += sector * k;
    const Jet<Order> rho = radiusScale * r;
    Jet<Order> sine, cosine;
    sinCos(angle, sine, cosine);
    px = rho * cosine;
    py = rho * sine;
  }

  /// toChart() for the polar form (degree != 6) that also gives |p| as a jet (the weight's
  /// argument), from the radius it computes anyway. Returns false, leaving px, py, norm as they
  /// are, for a rotation (degree 6).
  template <int Order>
  bool toChartWithNorm(const Jet<Order>& zx, const Jet<Order>& zy, int k, Jet<Order>& px,
                       Jet<Order>& py, Jet<Order>& norm) const {
    if (rotation) return false;
    const Jet<Order> r = sqrt(zx * zx + zy * zy);
    Jet<Order> angle = angleScale * atan2(zy, zx);
    angle.v += sector * k;
    norm = radiusScale * r;
    Jet<Order> sine, cosine;
    sinCos(angle, sine, cosine);
    px = norm * cosine;
    py = norm * sine;
    return true;
  }

  /// The canonical point of chart point p (jets) in sector k (p must not be 0 when Order > 0).
  /// The angle's value is measured from the sector's first ray.
  template <int Order>
  void toCanonical(const Jet<Order>& px, const Jet<Order>& py, int k, Jet<Order>& zx,
                   Jet<Order>& zy) const {
    const Jet<Order> r = (1.0 / radiusScale) * sqrt(px * px + py * py);
    Jet<Order> beta = atan2(py, px);
    // Bring the value into the sector; the derivatives do not depend on the branch.
    double value = beta.v - sector * k;
    while (value < -kPi) value += 2.0 * kPi;
    while (value > kPi) value -= 2.0 * kPi;
    beta.v = value;
    const Jet<Order> alpha = (1.0 / angleScale) * beta;
    Jet<Order> sine, cosine;
    sinCos(alpha, sine, cosine);
    zx = r * cosine;
    zy = r * sine;
  }

  /// toCanonical() for chart point jets p in sector k whose canonical point z (the value) is
  /// already known, without trigonometry: the angle's cosine and sine are z / |z|, its
  /// derivatives those of the polar angle of p divided by angleScale. The values of zx, zy are
  /// z itself. p (and z) must not be 0 when Order > 0.
  /// `variables`: px and py are the independent variables (closed-form polar jets at Order 3).
  template <int Order>
  void toCanonicalAt(const Jet<Order>& px, const Jet<Order>& py, int k, const Eigen::Vector2d& z,
                     Jet<Order>& zx, Jet<Order>& zy, bool variables = false) const {
    if (rotation) {
      // The inverse rotation by 2 pi k / 6.
      double c, s;
      sixth(k, c, s);
      zx = c * px + s * py;
      zy = c * py - s * px;
    } else {
      Jet<Order> r, alpha;
      if constexpr (Order == 3) {
        if (variables) {
          polarJetsOfVariables(px.v, py.v, r, alpha);
          r = (1.0 / radiusScale) * r;
          alpha = (1.0 / angleScale) * alpha;
        }
      }
      if (Order != 3 || !variables) {
        r = (1.0 / radiusScale) * sqrt(px * px + py * py);
        alpha = (1.0 / angleScale) * polarAngle(py, px, 0.0);
      }
      const double length = z.norm();
      Jet<Order> sine, cosine;
      sinCosKnown(alpha, z.y() / length, z.x() / length, sine, cosine);
      zx = r * cosine;
      zy = r * sine;
    }
    zx.v = z.x();
    zy.v = z.y();
  }
};

/// PolarMap(degree), from a table built once per process for degrees up to 64 (the map's
/// constructor takes two cosines).
inline PolarMap polarMapOf(int degree) {
  constexpr int kTabled = 64;
  static const std::vector<PolarMap> table = [] {
    std::vector<PolarMap> maps;
    for (int n = 3; n <= kTabled; ++n) maps.emplace_back(n);
    return maps;
  }();
  return degree >= 3 && degree <= kTabled ? table[static_cast<std::size_t>(degree - 3)]
                                          : PolarMap(degree);
}

}  // namespace d2vdb::detail
