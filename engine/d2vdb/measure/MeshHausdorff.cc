#include "d2vdb/measure/MeshHausdorff.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/measure/detail/CertifiedDistance.h"
#include "d2vdb/measure/detail/HausdorffPieces.h"
#include "d2vdb/measure/detail/TargetDistance.h"

namespace d2vdb {
namespace {

using detail::kUnitRoundoff;
using detail::NetPiece;
using detail::PointBound;
using detail::TargetDistance;
using detail::TrianglePiece;

constexpr double kNoBound = std::numeric_limits<double>::infinity();

/// The best lower bound so far and where it is attained.
struct Witness {
  double lower = -kNoBound;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();

  void offer(double value, const Eigen::Vector3d& at, const Eigen::Vector3d& nearest) {
    if (value > lower) *this = {value, at, nearest};
  }
};

/// The largest coordinate magnitude of a shape's points and control points.
double coordinateScale(const HausdorffShape& shape) {
  double scale = 0.0;
  for (const Eigen::Vector3d& point : shape.points) {
    scale = std::max(scale, detail::largestMagnitude(point));
  }
  for (const BezierNet& net : shape.nets) {
    for (const Eigen::Vector3d& point : net.controls) {
      scale = std::max(scale, detail::largestMagnitude(point));
    }
  }
  return scale;
}

/// How many roundings of the coordinate scale one subdivision level adds to a piece's points:
/// 1 for a midpoint of a triangle's edge, p + q (+ 1 for safety) for de Casteljau at 1/2 in both
/// directions of a net of degrees (p, q).
double roundingsPerLevel(const HausdorffShape& from) {
  double roundings = 1.0;
  for (const BezierNet& net : from.nets) {
    roundings = std::max(roundings, double(net.degreeU + net.degreeV + 1));
  }
  return roundings;
}

/// The refinement of one direction: rounds of bounding and splitting (see certifiedHausdorff()),
/// over pieces of A's triangles (TrianglePiece) or of its Bézier nets (NetPiece).
template <class Piece>
class DirectedRefinement {
 public:
  /// Pieces settle once their upper bound is within `tolerance` of the larger of the best lower
  /// bound and `floor` (a lower bound already known of what the caller needs, or -infinity).
  DirectedRefinement(const HausdorffShape& from, const TargetDistance& target, double tolerance,
                     double floor, const CertifiedHausdorffOptions& options, std::string stage)
      : from_(from),
        target_(target),
        tolerance_(tolerance),
        options_(options),
        stage_(std::move(stage)),
        floor_(floor) {}

  DirectedHausdorffBracket run() {
    std::vector<Piece> pieces = firstRound();
    while (!pieces.empty()) {
      pieces = refineRound(pieces.size(), [&](std::size_t i) -> const Piece& { return pieces[i]; });
    }
    finish();
    return std::move(result_);
  }

 private:
  std::vector<Piece> firstRound();

  // Certified bounds of a new corner, offered as a witness.
  PointBound boundCorner(const Eigen::Vector3d& point, Witness& found) const {
    const PointBound bound = target_.point(point);
    found.offer(bound.lower, point, bound.closest);
    return bound;
  }

  // An upper bound of the distance over the piece, from the cheapest bound that settles it: the
  // 1-Lipschitz bound from its corners, then the convex bound over one target triangle
  // (hullUpper()). (A Lipschitz bound from the piece's centre, tried, cost a point query per
  // piece and settled almost none: the torus benchmark ran 2x slower.)
  double boundPiece(const Piece& piece, double threshold) const {
    const double upper = piece.lipschitzUpper();
    if (upper <= threshold || !piece.splittable()) return upper;
    return target_.hullUpper(piece.hull(), piece.hullCount(), threshold, upper);
  }

  // One round over `count` pieces, the i-th given by pieceAt(i): bound every piece, settle those
  // within the tolerance (or not refinable), split the others. Returns the children.
  template <class PieceAt>
  std::vector<Piece> refineRound(std::size_t count, const PieceAt& pieceAt) {
    const double threshold = std::max(witness_.lower, floor_) + tolerance_;
    std::vector<double> uppers(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          uppers[i] = boundPiece(pieceAt(i), threshold);
                        }
                      });
    std::vector<std::size_t> splitting;
    std::size_t childCount = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (uppers[i] <= threshold) {
        settled_ = std::max(settled_, uppers[i]);
        continue;
      }
      const Piece& piece = pieceAt(i);
      if (!refinable(piece, childCount)) {
        settled_ = std::max(settled_, uppers[i]);
        markUnconverged(piece);
        continue;
      }
      splitting.push_back(i);
      childCount += piece.childCount();
    }
    std::vector<Piece> children = split(pieceAt, splitting);
    result_.primitivesRefined += splitting.size();
    reportProgress(children);
    return children;
  }

  bool refinable(const Piece& piece, std::size_t childrenSoFar) const {
    const std::size_t bytes = sizeof(Piece) + sizeof(Eigen::Vector3d) * piece.hullCount();
    const std::size_t limit = std::min(options_.maxPieces, options_.maxPieceBytes / bytes);
    return piece.splittable() && piece.depth < options_.maxDepth &&
           childrenSoFar + piece.childCount() <= limit;
  }

  void markUnconverged(const Piece& piece) {
    if (!result_.converged) return;
    result_.converged = false;
    if (!piece.splittable()) {
      result_.warning = "the tolerance is below the rounding of the distances at a point";
    } else if (piece.depth >= options_.maxDepth) {
      result_.warning = "a primitive reached the subdivision limit (" +
                        std::to_string(options_.maxDepth) + " halvings) before the tolerance";
    } else {
      result_.warning = "the refinement reached its limit of pieces (" +
                        std::to_string(options_.maxPieces) + ", " +
                        std::to_string(options_.maxPieceBytes >> 20) +
                        " MiB) before the tolerance: the bracket reached is reported";
    }
  }

  // The children of the split pieces, in piece order, with their new corners bounded; the
  // lower bound and witness are updated in the same order.
  template <class PieceAt>
  std::vector<Piece> split(const PieceAt& pieceAt, const std::vector<std::size_t>& splitting) {
    std::vector<std::size_t> firstChild(splitting.size() + 1, 0);
    for (std::size_t s = 0; s < splitting.size(); ++s) {
      firstChild[s + 1] = firstChild[s] + pieceAt(splitting[s]).childCount();
    }
    std::vector<Piece> children(firstChild.back());
    std::vector<Witness> found(splitting.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, splitting.size(), 8),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t s = range.begin(); s != range.end(); ++s) {
                          pieceAt(splitting[s])
                              .split(&children[firstChild[s]], [&](const Eigen::Vector3d& point) {
                                return boundCorner(point, found[s]).upper;
                              });
                        }
                      });
    for (const Witness& candidate : found) {
      witness_.offer(candidate.lower, candidate.point, candidate.closest);
    }
    return children;
  }

  // The share of `from` (by primitive, a child counting a quarter or half of its parent) that is
  // settled.
  void reportProgress(const std::vector<Piece>& children) {
    if (children.empty()) return;
    result_.deepestLevel = std::max(result_.deepestLevel, int(children.front().depth));
    if (!options_.progress) return;
    double open = 0.0;
    for (const Piece& child : children) open += child.share();
    options_.progress(stage_, std::clamp(1.0 - open / initialCount_, 0.0, 1.0));
  }

  // The points of refined pieces are off the exact ones by at most a rounding of the coordinate
  // scale per coordinate, level and rounding step (roundingsPerLevel()), on top of their
  // parents' error: 2 (depth + 1) roundings u s as a vector bounds it.
  void finish() {
    const double points = 2.0 * (result_.deepestLevel + 1) * roundingsPerLevel(from_) *
                          kUnitRoundoff * coordinateScale(from_);
    result_.lower = std::max(0.0, witness_.lower - points);
    result_.upper = std::max(settled_, witness_.lower) + points;
    result_.witness = witness_.point;
    result_.witnessClosest = witness_.closest;
    if (options_.progress) options_.progress(stage_, 1.0);
  }

  const HausdorffShape& from_;
  const TargetDistance& target_;
  double tolerance_;
  const CertifiedHausdorffOptions& options_;
  std::string stage_;
  DirectedHausdorffBracket result_;
  Witness witness_;
  double settled_ = 0.0;
  double initialCount_ = 1.0;
  double floor_;
};

// Triangles: every point of A is bounded first (the heat map's values and the first lower
// bound), then the first round makes its pieces from the triangles as it goes.
template <>
std::vector<TrianglePiece> DirectedRefinement<TrianglePiece>::firstRound() {
  const std::vector<Eigen::Vector3d>& points = from_.points;
  std::vector<PointBound> bounds(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        bounds[i] = target_.point(points[i]);
                      }
                    });
  // Only corners of primitives are points of the shape (a mesh may carry unused vertices).
  std::vector<bool> used(points.size(), false);
  for (const TriangleIndices& triangle : from_.triangles) {
    for (const std::uint32_t corner : triangle) used[corner] = true;
  }
  result_.pointDistances.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    result_.pointDistances[i] = bounds[i].upper;
    if (used[i]) witness_.offer(bounds[i].lower, points[i], bounds[i].closest);
  }
  initialCount_ = static_cast<double>(from_.triangles.size());
  return refineRound(from_.triangles.size(), [&](std::size_t i) {
    return detail::trianglePiece(from_, from_.triangles[i], result_.pointDistances);
  });
}

// Bézier nets: the corners of every net are bounded first, in parallel, offered in net order.
template <>
std::vector<NetPiece> DirectedRefinement<NetPiece>::firstRound() {
  std::vector<NetPiece> pieces(from_.nets.size());
  std::vector<Witness> found(pieces.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size(), 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        pieces[i] = detail::netPiece(from_.nets[i]);
                        for (int k = 0; k < pieces[i].cornerCount(); ++k) {
                          pieces[i].cornerUpper[k] =
                              boundCorner(pieces[i].corner(k), found[i]).upper;
                        }
                      }
                    });
  for (const Witness& candidate : found) {
    witness_.offer(candidate.lower, candidate.point, candidate.closest);
  }
  initialCount_ = static_cast<double>(pieces.size());
  return refineRound(pieces.size(), [&](std::size_t i) -> const NetPiece& { return pieces[i]; });
}

/// h(from -> to) to within `tolerance` for the pieces (nets when `from` has them, else its
/// triangles), before the shapes' approximation errors are added.
DirectedHausdorffBracket refineDirection(const HausdorffShape& from, const TargetDistance& to,
                                         double tolerance, double floor,
                                         const CertifiedHausdorffOptions& options,
                                         const std::string& stage) {
  if (!from.nets.empty()) {
    return DirectedRefinement<NetPiece>(from, to, tolerance, floor, options, stage).run();
  }
  return DirectedRefinement<TrianglePiece>(from, to, tolerance, floor, options, stage).run();
}

/// What a shape adds to the bracket's error as the side measured from (its nets are exact) and
/// as the target (its triangles).
double errorAsFrom(const HausdorffShape& shape) {
  return shape.nets.empty() ? shape.approximationError : 0.0;
}

void requireFinite(const std::vector<Eigen::Vector3d>& points, const char* name) {
  for (const Eigen::Vector3d& point : points) {
    if (!point.allFinite()) {
      throw InputError(std::string("shape ") + name + " has a non-finite coordinate");
    }
  }
}

// A shape measured from needs triangles or nets; a target needs triangles.
void requireShape(const HausdorffShape& shape, const char* name, bool asTarget) {
  if (shape.triangles.empty() && (asTarget || shape.nets.empty())) {
    throw InputError(std::string("shape ") + name +
                     (shape.nets.empty() ? " has no primitives"
                                         : " is a spline without a tessellation to measure to"));
  }
  requireFinite(shape.points, name);
  for (const TriangleIndices& triangle : shape.triangles) {
    for (const std::uint32_t corner : triangle) {
      if (corner >= shape.points.size()) {
        throw InputError(std::string("a primitive of shape ") + name + " names point " +
                         std::to_string(corner) + " of " + std::to_string(shape.points.size()));
      }
    }
  }
  for (const BezierNet& net : shape.nets) {
    const bool sized = net.degreeU >= 1 && net.degreeU <= 15 && net.degreeV >= 0 &&
                       net.degreeV <= 15 &&
                       net.controls.size() == std::size_t(net.degreeU + 1) * (net.degreeV + 1);
    if (!sized) throw InputError(std::string("a Bézier net of shape ") + name + " is malformed");
    requireFinite(net.controls, name);
  }
  if (!(shape.approximationError >= 0.0) || !std::isfinite(shape.approximationError)) {
    throw InputError(std::string("shape ") + name + " has an invalid approximation error");
  }
}

void requireOptions(const CertifiedHausdorffOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    throw InputError("the Hausdorff tolerance must be a positive finite number, not " +
                     formatNumber(options.tolerance));
  }
  if (options.maxDepth < 1 || options.maxDepth > 40) {
    throw InputError("the Hausdorff subdivision depth must be 1..40, not " +
                     std::to_string(options.maxDepth));
  }
  if (options.maxPieces < 4) throw InputError("the Hausdorff piece limit must be at least 4");
}

// Widens a bracket of the pieces' distance into one of the shapes' distance.
void widen(DirectedHausdorffBracket& bracket, double error) {
  bracket.lower = std::max(0.0, bracket.lower - error);
  bracket.upper += error;
}

// The tolerance the refinement works to: the requested one less what the shapes' tessellation
// errors and the rounding of refined points add to the bracket's width.
double refinementTolerance(const HausdorffShape& from, const HausdorffShape& to, double tolerance,
                           int maxDepth) {
  const double shapes = 2.0 * (errorAsFrom(from) + to.approximationError);
  if (!(tolerance > shapes)) {
    throw InputError("the tolerance " + formatNumber(tolerance) +
                     " is not larger than twice the shapes' tessellation errors (" +
                     formatNumber(shapes) + "): tessellate more finely");
  }
  const double scale = std::max(coordinateScale(from), coordinateScale(to));
  const double rounding = 4.0 * (maxDepth + 1) * roundingsPerLevel(from) * kUnitRoundoff * scale;
  if (!(tolerance - shapes > 2.0 * rounding)) {
    throw InputError("the tolerance " + formatNumber(tolerance) +
                     " is below what double precision resolves at coordinates of magnitude " +
                     formatNumber(scale) + " (about " + formatNumber(2.0 * rounding) + ")");
  }
  return tolerance - shapes - rounding;
}

// h(from -> to), its bracket widened by the shapes' errors. With a finite `floor` (a certified
// lower bound of what the caller needs, in the widened bracket's terms), pieces settle within the
// tolerance of the floor: the upper bound then stays within the tolerance of max(floor, h).
DirectedHausdorffBracket measureDirection(const HausdorffShape& from, const HausdorffShape& to,
                                          const TargetDistance& target, double tolerance,
                                          double floor, const CertifiedHausdorffOptions& options,
                                          const std::string& stage) {
  const double error = errorAsFrom(from) + to.approximationError;
  DirectedHausdorffBracket bracket =
      refineDirection(from, target, refinementTolerance(from, to, tolerance, options.maxDepth),
                      floor - error, options, stage);
  widen(bracket, error);
  return bracket;
}

}  // namespace

DirectedHausdorffBracket directedHausdorff(const HausdorffShape& from, const HausdorffShape& to,
                                           double tolerance,
                                           const CertifiedHausdorffOptions& options) {
  requireShape(from, "A", false);
  requireShape(to, "B", true);
  CertifiedHausdorffOptions absolute = options;
  absolute.tolerance = tolerance;
  absolute.relative = false;
  requireOptions(absolute);
  const TargetDistance target(to);
  return measureDirection(from, to, target, tolerance, -kNoBound, absolute, "h(A -> B)");
}

CertifiedHausdorff certifiedHausdorff(const HausdorffShape& a, const HausdorffShape& b,
                                      const CertifiedHausdorffOptions& options) {
  requireShape(a, "A", true);
  requireShape(b, "B", true);
  requireOptions(options);
  CertifiedHausdorff result;
  result.tolerance = options.tolerance;
  if (options.relative) {
    const double diagonal = combinedDiagonal(a, b);
    result.tolerance = diagonal > 0.0 ? options.tolerance * diagonal : options.tolerance;
  }
  result.aToB =
      measureDirection(a, b, TargetDistance(b), result.tolerance, -kNoBound, options, "h(A -> B)");
  // Both directed brackets to the tolerance, or h(B -> A) only as far as H needs it.
  const double floor = options.tightDirections ? -kNoBound : result.aToB.lower;
  result.bToA =
      measureDirection(b, a, TargetDistance(a), result.tolerance, floor, options, "h(B -> A)");
  result.aToBIsLarger = result.aToB.lower >= result.bToA.lower;
  result.lower = std::max(result.aToB.lower, result.bToA.lower);
  result.upper = std::max(result.aToB.upper, result.bToA.upper);
  return result;
}

std::vector<double> pointDistancesTo(const HausdorffShape& to,
                                     const std::vector<Eigen::Vector3d>& points) {
  requireShape(to, "B", true);
  requireFinite(points, "A");
  const TargetDistance target(to);
  std::vector<double> distances(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        distances[i] = target.point(points[i]).upper;
                      }
                    });
  return distances;
}

}  // namespace d2vdb
