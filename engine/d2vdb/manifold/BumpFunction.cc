#include "d2vdb/manifold/BumpFunction.h"

#include <cmath>

namespace d2vdb {

BumpValue chartBump(double t) {
  if (std::isnan(t)) return {t, t, t};
  if (t <= kBumpInner) return {1.0, 0.0, 0.0};
  if (t >= 1.0) return {0.0, 0.0, 0.0};
  constexpr double kWidth = 1.0 - kBumpInner;
  const double h = (t - kBumpInner) / kWidth;
  const double s = 1.0 / (1.0 - h) - 1.0 / h;
  // exp(2 s) overflows beyond s ~ 354 and xi = 1 to double precision below s ~ -19; the
  // derivatives carry the factor xi (1 - xi) < exp(-2 |s|), far below anything they multiply.
  if (s > 350.0) return {0.0, 0.0, 0.0};
  if (s < -350.0) return {1.0, 0.0, 0.0};
  const double e = std::exp(2.0 * s);
  const double xi = 1.0 / (1.0 + e);
  const double q = xi * e / (1.0 + e);  // xi (1 - xi), without cancellation
  // d xi / ds = -2 q, d^2 xi / ds^2 = 4 q (1 - 2 xi).
  const double dXi = -2.0 * q;
  const double ddXi = 4.0 * q * (1.0 - 2.0 * xi);
  const double u = 1.0 - h;
  const double dS = 1.0 / (u * u) + 1.0 / (h * h);
  const double ddS = 2.0 / (u * u * u) - 2.0 / (h * h * h);
  const double dH = 1.0 / kWidth;
  return {xi, dXi * dS * dH, (ddXi * dS * dS + dXi * ddS) * dH * dH};
}

}  // namespace d2vdb
