// Real roots of a scalar polynomial in Bernstein form on [0, 1], by subdivision root isolation.
#pragma once

#include <vector>

#include "d2vdb/spline/Bernstein.h"

namespace d2vdb::detail {

/// Controls of findBernsteinRoots().
struct RootIsolationOptions {
  /// Width (in the polynomial's parameter, [0, 1]) below which an interval that may still hold
  /// roots is reported as one root: a multiple root or a cluster closer than this. Must be > 0.
  double parameterTolerance = 1e-13;
  /// Bound on the clipping/subdivision steps along any path of the recursion; an interval at
  /// this depth is reported as one root and depthLimitReached is set. Must be >= 1.
  int maxDepth = 120;
};

/// What findBernsteinRoots() found.
struct BernsteinRootSet {
  /// The roots in [0, 1], ascending, each reported once (a multiple root or a cluster narrower
  /// than the tolerance counts as one).
  std::vector<double> roots;
  /// True when every coefficient is exactly zero: every t is a root and `roots` is empty.
  bool identicallyZero = false;
  /// True when some interval reached RootIsolationOptions::maxDepth.
  bool depthLimitReached = false;
};

/// The real roots of f(t) = sum_i c_i B_{i,n}(t) in [0, 1].
///
/// Method: convex-hull pruning (an interval is dropped when all its Bernstein coefficients lie
/// strictly on one side of a noise band around zero, the band being a few ulps of the largest
/// coefficient), Bézier clipping of the interval to where the coefficients' convex hull meets the
/// band, midpoint subdivision when clipping shrinks the interval by less than half, and, once
/// Descartes' rule of signs proves a single simple root (one sign change among the coefficients,
/// opposite signs at both ends), a bracketed Newton iteration polishes it to full precision.
/// Roots at the ends of [0, 1] and at subdivision points are found (the noise band keeps the
/// intervals that touch them). Throws InputError for invalid options.
BernsteinRootSet findBernsteinRoots(const BernsteinPolynomial& f,
                                    const RootIsolationOptions& options = {});

}  // namespace d2vdb::detail
