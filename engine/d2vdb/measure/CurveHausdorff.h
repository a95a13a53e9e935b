// Exact Hausdorff distance between two B-spline curves (Chen, Ma, Xu and Paul, "Computing the
// Hausdorff distance between two B-spline curves", Computer-Aided Design 2010; engine/README.md),
// with a certified bracket.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// Controls of the Hausdorff computation.
struct HausdorffOptions {
  /// Target width of the certified bracket [lowerBound, upperBound] of each one-sided distance,
  /// relative to the size of the pair (the diagonal of the bounding box of both curves' control
  /// points). Must be > 0 and finite.
  double relativeTolerance = 1e-10;
  /// Bound on the number of halvings of one knot span of the `from` curve. Must be 1..200.
  int maxDepth = 64;
  /// Bound on the total number of sub-intervals examined by one one-sided computation. Must be
  /// >= 1.
  std::size_t maxIntervals = 1000000;
};

/// Where the Hausdorff pair lies (the four cases of Chen et al. 2010). An "end point" is an end of
/// an open curve or a knot where the tangent direction jumps (a C1 discontinuity).
enum class HausdorffCase {
  EndPoints = 1,            ///< case 1: an end point of each curve
  EndPointAndInterior = 2,  ///< case 2: an end point of one curve, an interior point of the other
  MutuallyOrthogonal = 3,   ///< case 3: interior points, C1 - C2 orthogonal to both tangents
  Bisector = 4  ///< case 4: an interior `from` point with two or more nearest points (which may
                ///< be end points of `to`)
};

/// The name of a case as reports give it: "end points", "end point and interior point",
/// "mutually orthogonal interior points" or "bisector (several nearest points)".
const char* hausdorffCaseName(HausdorffCase pairCase);

/// The one-sided Hausdorff distance h(from -> to) = max_u min_v |from(u) - to(v)|.
struct OneSidedHausdorff {
  /// min_v |from(u) - to(v)| at the reported u: an attained value, equal to lowerBound.
  double distance = 0.0;
  /// Certified bracket: lowerBound <= h(from -> to) <= upperBound (up to floating-point
  /// rounding in the evaluation of the curves).
  double lowerBound = 0.0;
  double upperBound = 0.0;
  double fromParameter = 0.0;  ///< u, in from's domain
  double toParameter = 0.0;    ///< v, in to's domain: a nearest point of from(u)
  Eigen::Vector3d fromPoint = Eigen::Vector3d::Zero();  ///< from(u)
  Eigen::Vector3d toPoint = Eigen::Vector3d::Zero();    ///< to(v)
  HausdorffCase pairCase = HausdorffCase::EndPoints;
  /// True when upperBound - lowerBound <= the tolerance; false when maxDepth or maxIntervals
  /// stopped the subdivision first (`warnings` then says which).
  bool converged = true;
  std::size_t intervalsExamined = 0;  ///< sub-intervals of from's parameter processed
  int deepestLevel = 0;               ///< largest subdivision depth reached
  std::vector<std::string> warnings;
};

/// The two-sided Hausdorff distance H(a, b) = max(h(a -> b), h(b -> a)).
struct HausdorffDistance {
  OneSidedHausdorff aToB;    ///< h(a -> b)
  OneSidedHausdorff bToA;    ///< h(b -> a)
  double distance = 0.0;     ///< max of the two one-sided distances
  double lowerBound = 0.0;   ///< max of the two lower bounds
  double upperBound = 0.0;   ///< max of the two upper bounds
  bool aToBIsLarger = true;  ///< which one-sided distance is H (ties: a -> b)
};

/// h(from -> to) to within HausdorffOptions::relativeTolerance of the pair's size.
///
/// Method (Chen et al. 2010). Work items are sub-intervals L of the knot spans of
/// `from`, each with the list of `to` spans that can hold a nearest point for some u in L and the
/// nearest points ("feet") of its two ends.
///  - Lower bound: exact values of d(u) = min_v |from(u) - to(v)| (CurveProjector::nearest) at
///    every knot of `from` (the end-point cases 1 and 2), at the centre of every item, at the
///    solution of the mutually orthogonal case 3 found by Newton's method from the centre, and,
///    where the feet of an item's ends lie apart, at the bisector point of case 4 found by
///    Newton's method on the trivariate system (equidistant from two orthogonal feet).
///  - Upper bound of max_{u in L} d(u)^2: the largest Bernstein coefficient of
///    S(u, phi(u)) = |from(u) - to(phi(u))|^2, valid for any phi since d(u)^2 <= S(u, v); the
///    smallest of three: phi constant at the centre's foot, phi the first-order (derivative-based)
///    model of the nearest-point map v(u) at the centre (Chen et al.'s "v(u) as piecewise linear
///    functions"), and phi interpolating the two end feet (exact at the ends of L).
///  - Elimination: L is dropped when its upper bound does not exceed the best lower bound; `to`
///    spans are dropped from L's list when the smallest coefficient of the tensor-product
///    Bernstein form of S(u, v) over L x span (SquaredDistanceTensor) exceeds L's upper bound.
///  - Termination: L is settled when its upper bound is within the tolerance of the best lower
///    bound; otherwise it is halved, at its bisector point when it has one (each half then follows
///    one branch of the nearest-point map) or else in the middle.
/// The items of one subdivision level are processed in parallel (TBB) and reduced in a fixed
/// order, so every result is identical for any thread count. Subdivision is bounded by
/// maxDepth and maxIntervals: hitting a bound returns the bracket reached, converged = false and
/// a warning, never a hang. Throws InputError for invalid options.
OneSidedHausdorff oneSidedHausdorff(const BSplineCurve& from, const BSplineCurve& to,
                                    const HausdorffOptions& options = {});

/// H(a, b): both one-sided distances (computed concurrently), each as oneSidedHausdorff().
HausdorffDistance hausdorffDistance(const BSplineCurve& a, const BSplineCurve& b,
                                    const HausdorffOptions& options = {});

}  // namespace d2vdb
