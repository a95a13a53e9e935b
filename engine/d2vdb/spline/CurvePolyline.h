// B-spline curves as polylines: for drawing, and for their length.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <initializer_list>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// How many points draw `curve` as a smooth polyline: 64 per polynomial piece (Bézier segment,
/// BSplineCurve::toBezierSegments()), at least 512 and at most 20000. Never throws (beyond
/// std::bad_alloc).
int drawingPointCount(const BSplineCurve& curve);

/// `curves` as polylines drawn together: each one's BSplineCurve::sample() at the largest
/// drawingPointCount() among them, so that every curve of one drawing has the same number of
/// points (none drawn coarser than the most detailed one). The polylines are in the order of
/// `curves`; an empty list gives none. Never throws (beyond std::bad_alloc).
std::vector<std::vector<Eigen::Vector3d>> drawingPolylines(
    std::initializer_list<std::reference_wrapper<const BSplineCurve>> curves);

/// The length (world units) of the polyline through `samples` (>= 2) points of `curve` equally
/// spaced in parameter (BSplineCurve::sample()): a lower bound of the curve's arc length that
/// converges to it quadratically in the spacing. Throws InputError for fewer than 2 samples.
double sampledLength(const BSplineCurve& curve, int samples = 1025);

}  // namespace d2vdb
