// Volume, area and the Steiner coefficients of a closed support-function surface.
#pragma once

#include "d2vdb/support/SupportFunction.h"

namespace d2vdb {

/// Integrals over the whole sphere of normals, with W = Hess_S h + h I (world units):
///   area   A = integral det W d omega                 (surface area)
///   volume V = (1/3) integral h det W d omega          (enclosed volume)
///   mean   M = integral h d omega = integral (r1 + r2)/2 d omega   (integral of mean curvature)
/// For a closed convex surface these are its area, volume and the quadratic coefficient of
/// Steiner's formula V(d) = V + A d + M d^2 + (4 pi / 3) d^3 for its offsets (Groemer, Geometric
/// Applications of Fourier Series and Spherical Harmonics, 1996, sec. 5.3); for other h they are
/// the signed (algebraic) quantities of the possibly singular surface x_h. The integrands are
/// polynomials of degree <= 3L + 4 on the sphere and are integrated exactly (to rounding) by a
/// product rule.
struct SupportMeasures {
  double area = 0.0;
  double volume = 0.0;
  double meanCurvatureIntegral = 0.0;

  /// Steiner's polynomial: the volume enclosed by the offset at distance d.
  double offsetVolume(double d) const {
    return volume + area * d + meanCurvatureIntegral * d * d +
           4.18879020478639098 * d * d * d;  // 4 pi / 3
  }
};

/// The measures of x_h over the whole sphere.
SupportMeasures supportMeasures(const SupportFunction& h);

}  // namespace d2vdb
