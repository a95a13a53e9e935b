// The straight rulings of a (piecewise) ruled B-spline surface of degree (1, n): the lines a hot
// wire or a wire-EDM electrode follows (Pottmann, Leopoldseder and Hofer 2002).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// One straight segment of a ruled surface: S(u, v) for u over one knot span of u at fixed v.
struct Ruling {
  double v = 0.0;                                   ///< the parameter along the rulings' family
  int piece = 0;                                    ///< which u span (0 for a single ruled strip)
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  ///< S(u_a, v)
  Eigen::Vector3d end = Eigen::Vector3d::Zero();    ///< S(u_b, v)
};

/// The rulings of a surface of degree 1 in u at the v knots of its domain and at `samplesPerSpan`
/// equally spaced parameters inside every v span (a closed v direction lists its seam once), for
/// every u span (countU() - 1 pieces with clamped knots), ordered by v, then piece. Because the
/// surface is linear in u on each span, every ruling lies on it exactly. InputError when the degree
/// in u is not 1 or samplesPerSpan is negative.
std::vector<Ruling> surfaceRulings(const BSplineSurface& surface, int samplesPerSpan);

/// How many rulings surfaceRulings() returns, without making them: (v spans * (samplesPerSpan +
/// 1) + 1 [open v]) * u spans. A double, so that absurd requests do not overflow.
double surfaceRulingCount(const BSplineSurface& surface, int samplesPerSpan);

}  // namespace d2vdb
