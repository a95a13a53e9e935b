#include "d2vdb/manifold/BumpFunction.h"

#include <cmath>

namespace d2vdb {

BumpValue chartBump(double t) {
  if (std::isnan(t)) return {t, t, t, t};
  if (t <= kBumpInner) return {1.0, 0.0, 0.0};
  if (t >= 1.0) return {0.0, 0.0, 0.0};
  constexpr double kWidth = 1.0 - kBumpInner;
  constexpr double dH = 1.0 / kWidth;
  const double h = (t - kBumpInner) / kWidth;  // exactly 1/2 at the midpoint t = 5/8
  // Three divisions in all: this one, 1 / (h (1 - h)) (giving 1 / (1 - h) and 1 / h) and
  // 1 / (1 + exp(2 s)).
  const double inverseProduct = 1.0 / (h * (1.0 - h));
  const double inverseU = h * inverseProduct;
  const double inverseH = (1.0 - h) * inverseProduct;
  const double s = inverseU - inverseH;
  // exp(2 s) overflows beyond s ~ 354 and xi = 1 to double precision below s ~ -19; the
  // derivatives carry the factor xi (1 - xi) < exp(-2 |s|), far below anything they multiply.
  if (s > 350.0) return {0.0, 0.0, 0.0};
  if (s < -350.0) return {1.0, 0.0, 0.0};
  const double e = std::exp(2.0 * s);
  const double xi = 1.0 / (1.0 + e);
  const double q = xi * (e * xi);  // xi (1 - xi) = xi e / (1 + e), without cancellation
  // d xi / ds = -2 q, d^2 xi / ds^2 = 4 q (1 - 2 xi), d^3 xi / ds^3 = 16 q^2 - 8 q (1 - 2 xi)^2
  // (dq / ds = -2 q (1 - 2 xi)).
  const double dXi = -2.0 * q;
  const double across = 1.0 - 2.0 * xi;
  const double ddXi = 4.0 * q * across;
  const double dddXi = 16.0 * q * q - 8.0 * q * across * across;
  // ds/dh = 1 / u^2 + 1 / h^2, d2s/dh2 = 2 / u^3 - 2 / h^3, d3s/dh3 = 6 / u^4 + 6 / h^4
  // (u = 1 - h).
  const double inverseU2 = inverseU * inverseU;
  const double inverseH2 = inverseH * inverseH;
  const double dS = inverseU2 + inverseH2;
  const double ddS = 2.0 * (inverseU2 * inverseU - inverseH2 * inverseH);
  const double dddS = 6.0 * (inverseU2 * inverseU2 + inverseH2 * inverseH2);
  return {xi, dXi * dS * dH, (ddXi * dS * dS + dXi * ddS) * dH * dH,
          (dddXi * dS * dS * dS + 3.0 * ddXi * dS * ddS + dXi * dddS) * dH * dH * dH};
}

}  // namespace d2vdb
