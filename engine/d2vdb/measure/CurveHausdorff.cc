// The exact curve-curve Hausdorff distance: the one-sided search over Bernstein bounds
// (OneSidedSearch), bisector cases and the final classification.
#include "d2vdb/measure/CurveHausdorff.h"

#include <Eigen/LU>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/measure/PointProjection.h"
#include "d2vdb/measure/detail/SquaredDistanceTensor.h"

namespace d2vdb {

using detail::SquaredDistanceTensor;
namespace {

constexpr double kDoubleEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The `to` segments an item must search; null means all of them (searched through the box tree).
using CandidateList = std::shared_ptr<const std::vector<int>>;

// An exact value of d(u)^2 = min_v |from(u) - to(v)|^2 at one u.
struct Sample {
  double squaredDistance = -kInfinity;
  int fromSegment = -1;
  double fromLocal = 0.0;  // u as the parameter of the `from` segment, [0, 1]
  NearestPoint nearest;    // on `to`
};

// A sub-interval [start, end] of one knot span of `from` (in the segment's parameter [0, 1]).
struct WorkItem {
  int segment = 0;
  double start = 0.0;
  double end = 1.0;
  int depth = 0;
  double parentBound = kInfinity;  // the parent's upper bound of max d^2 (a bound for this one)
  SegmentPoint hint;               // nearest point of the parent's centre
  SegmentPoint startFoot;          // nearest point on `to` of from(start)
  SegmentPoint endFoot;            // nearest point on `to` of from(end)
  CandidateList candidates;        // `to` segments that can hold a nearest point
};

// What processing one item found.
struct ItemOutcome {
  Sample center;
  Sample orthogonal;  // Newton solution of case 3, if it converged inside the item
  Sample bisector;    // Newton solution of case 4, if it converged inside the item
  double upperBound = kInfinity;
};

// Shared, read-only state of one one-sided computation.
struct Problem {
  const CurveProjector& from;
  const CurveProjector& to;
  double tolerance;  // absolute, in distance units
};

BezierCurve pieceOf(const CurveProjector::Segment& segment, double start, double end) {
  if (start == 0.0 && end == 1.0) return segment.curve;
  return segment.curve.restricted(start, end);
}

// The largest Bernstein coefficient of |a(s) - b(s)|^2 (an upper bound of it on [0, 1]) plus a
// rounding margin; a and b are written with a common degree first.
double maxSquaredDifference(const BezierCurve& a, const BezierCurve& b) {
  const int degree = std::max(a.degree(), b.degree());
  const BezierCurve::ControlPoints difference = a.elevated(degree - a.degree()).controlPoints() -
                                                b.elevated(degree - b.degree()).controlPoints();
  const BezierCurve differenceCurve(difference);
  const BernsteinPolynomial squared = dot(differenceCurve, differenceCurve);
  const double largest = difference.colwise().squaredNorm().maxCoeff();
  return squared.maxCoefficient() + 16.0 * (2 * degree + 2) * kDoubleEpsilon * largest;
}

// Newton's method for the mutually orthogonal case 3 on piece x to-segment:
// (P(a) - Q(b)) . P'(a) = 0 and (P(a) - Q(b)) . Q'(b) = 0, from (0.5, b0). Returns (a, b) when it
// converges inside [0, 1]^2.
std::optional<std::pair<double, double>> solveOrthogonal(const BezierCurve& piece,
                                                         const CurveProjector::Segment& target,
                                                         double b0) {
  const BezierCurve velocityP = piece.derivative();
  const BezierCurve accelerationP = velocityP.derivative();
  const BezierCurve velocityQ = target.hodograph();
  const BezierCurve accelerationQ = velocityQ.derivative();
  double a = 0.5;
  double b = b0;
  for (int iteration = 0; iteration < 20; ++iteration) {
    const Eigen::Vector3d offset = piece.evaluate(a) - target.curve.evaluate(b);
    const Eigen::Vector3d dp = velocityP.evaluate(a);
    const Eigen::Vector3d dq = velocityQ.evaluate(b);
    Eigen::Matrix2d jacobian;
    jacobian << dp.squaredNorm() + offset.dot(accelerationP.evaluate(a)), -dp.dot(dq), dp.dot(dq),
        -dq.squaredNorm() + offset.dot(accelerationQ.evaluate(b));
    const Eigen::Vector2d residual(offset.dot(dp), offset.dot(dq));
    const double determinant = jacobian.determinant();
    const double scale = jacobian.cwiseAbs().maxCoeff();
    if (!(std::abs(determinant) > 1e-14 * scale * scale)) return std::nullopt;
    const Eigen::Vector2d step = -jacobian.inverse() * residual;
    if (!step.allFinite()) return std::nullopt;
    a += step.x();
    b += step.y();
    if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0) return std::nullopt;
    if (std::abs(step.x()) <= 1e-15 && std::abs(step.y()) <= 1e-15) return std::make_pair(a, b);
  }
  return std::nullopt;
}

Sample sampleAt(const Problem& problem, int segment, double local, const CandidateList& candidates,
                const std::optional<SegmentPoint>& hint) {
  const CurveProjector::Segment& fromSegment =
      problem.from.segments()[static_cast<std::size_t>(segment)];
  Sample sample;
  sample.fromSegment = segment;
  sample.fromLocal = local;
  const Eigen::Vector3d point = fromSegment.curve.evaluate(local);
  sample.nearest =
      candidates ? problem.to.nearest(point, *candidates, hint) : problem.to.nearest(point, hint);
  sample.squaredDistance = sample.nearest.squaredDistance;
  return sample;
}

// Upper bound of max_{u in item} d(u)^2: the smallest of the largest Bernstein coefficients of
// S(u, phi(u)) = |P(u) - Q(phi(u))|^2 (each a valid bound, as d(u)^2 <= S(u, v) for any v) with
// phi (a) constant at the centre's nearest point (segment j, parameter s), (b) the first-order
// model of the nearest-point map v(u) at the centre (implicit differentiation of
// (P - Q(v)) . Q'(v) = 0), clamped to segment j, and (c) when both end feet lie on one segment,
// the linear interpolation between them, exact at the item's ends (so a maximum at an end of the
// item is bounded tightly). centerBound() computes (a) and (b), interpolationBound() (c).
double centerBound(const Problem& problem, const BezierCurve& piece, const NearestPoint& nearest) {
  const CurveProjector::Segment& target =
      problem.to.segments()[static_cast<std::size_t>(nearest.location.segment)];
  const double s = nearest.location.segmentParameter;
  const Eigen::Vector3d targetPoint = target.curve.evaluate(s);
  const BezierCurve constant(std::vector<Eigen::Vector3d>{targetPoint});
  double bound = maxSquaredDifference(piece, constant);

  const Eigen::Vector3d offset = piece.evaluate(0.5) - targetPoint;
  const BezierCurve velocityQ = target.hodograph();
  const Eigen::Vector3d dq = velocityQ.evaluate(s);
  const double curvatureTerm = dq.squaredNorm() - offset.dot(velocityQ.derivative().evaluate(s));
  const double slope = piece.derivative().evaluate(0.5).dot(dq) / curvatureTerm;
  if (curvatureTerm > 0.0 && std::isfinite(slope) && slope != 0.0) {
    const double room = std::min(s, 1.0 - s);
    const double half = std::min(0.5 * std::abs(slope), room);
    const double phiStart = s - std::copysign(half, slope);
    const double phiEnd = s + std::copysign(half, slope);
    if (phiStart != phiEnd) {
      bound =
          std::min(bound, maxSquaredDifference(piece, target.curve.restricted(phiStart, phiEnd)));
    }
  }
  return bound;
}

// Bound (c) of the comment above: phi interpolates the feet of the item's ends when both lie on
// one `to` segment (infinity otherwise). Needs no projection, so it is tried first.
double interpolationBound(const Problem& problem, const WorkItem& item, const BezierCurve& piece) {
  if (item.startFoot.segment < 0 || item.startFoot.segment != item.endFoot.segment) {
    return kInfinity;
  }
  const CurveProjector::Segment& feet =
      problem.to.segments()[static_cast<std::size_t>(item.startFoot.segment)];
  const double from = item.startFoot.segmentParameter;
  const double to = item.endFoot.segmentParameter;
  const BezierCurve interpolated =
      from != to ? feet.curve.restricted(from, to)
                 : BezierCurve(std::vector<Eigen::Vector3d>{feet.curve.evaluate(from)});
  return maxSquaredDifference(piece, interpolated);
}

// Newton's method for the bisector case 4 on one `from` segment: the point X = from(u) is
// equidistant from A = to_j1(a) and B = to_j2(b): |X - A|^2 - |X - B|^2 = 0, and each foot is an
// orthogonal foot, (X - A) . A' = 0, unless it starts at an end of its segment (an end point or a
// corner of `to`, where the nearest point stays put): such a foot is held fixed and its equation
// dropped, so the system stays square (1 to 3 unknowns). Returns (u, a, b) when it converges
// with u in [uLow, uHigh] and a, b in [0, 1].
std::optional<Eigen::Vector3d> solveBisector(const CurveProjector::Segment& from,
                                             const CurveProjector::Segment& first,
                                             const CurveProjector::Segment& second, double u0,
                                             double a0, double b0, double uLow, double uHigh) {
  const BezierCurve velocityX = from.hodograph();
  const BezierCurve velocityA = first.hodograph();
  const BezierCurve accelerationA = velocityA.derivative();
  const BezierCurve velocityB = second.hodograph();
  const BezierCurve accelerationB = velocityB.derivative();
  // The unknowns (0: u, 1: a, 2: b) and equations (0: orthogonal at A, 1: orthogonal at B,
  // 2: equidistant) in use.
  std::array<int, 3> unknownIndex{};
  std::array<int, 3> equationIndex{};
  std::size_t size = 0;
  unknownIndex[size] = 0;
  equationIndex[size++] = 2;
  if (a0 > 0.0 && a0 < 1.0) {
    unknownIndex[size] = 1;
    equationIndex[size++] = 0;
  }
  if (b0 > 0.0 && b0 < 1.0) {
    unknownIndex[size] = 2;
    equationIndex[size++] = 1;
  }
  using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
  const auto count = static_cast<Eigen::Index>(size);
  Eigen::Vector3d unknowns(u0, a0, b0);
  for (int iteration = 0; iteration < 20; ++iteration) {
    const double u = unknowns.x();
    const double a = unknowns.y();
    const double b = unknowns.z();
    const Eigen::Vector3d x = from.curve.evaluate(u);
    const Eigen::Vector3d dx = velocityX.evaluate(u);
    const Eigen::Vector3d pointA = first.curve.evaluate(a);
    const Eigen::Vector3d da = velocityA.evaluate(a);
    const Eigen::Vector3d pointB = second.curve.evaluate(b);
    const Eigen::Vector3d db = velocityB.evaluate(b);
    const Eigen::Vector3d toA = x - pointA;
    const Eigen::Vector3d toB = x - pointB;
    const Eigen::Vector3d residual(toA.dot(da), toB.dot(db), toA.squaredNorm() - toB.squaredNorm());
    Eigen::Matrix3d jacobian;
    jacobian << dx.dot(da), -da.squaredNorm() + toA.dot(accelerationA.evaluate(a)), 0.0, dx.dot(db),
        0.0, -db.squaredNorm() + toB.dot(accelerationB.evaluate(b)),
        2.0 * (pointB - pointA).dot(dx), -2.0 * toA.dot(da), 2.0 * toB.dot(db);
    SmallMatrix reduced(count, count);
    SmallVector reducedResidual(count);
    for (std::size_t row = 0; row < size; ++row) {
      const auto r = static_cast<Eigen::Index>(row);
      reducedResidual[r] = residual[equationIndex[row]];
      for (std::size_t column = 0; column < size; ++column) {
        reduced(r, static_cast<Eigen::Index>(column)) =
            jacobian(equationIndex[row], unknownIndex[column]);
      }
    }
    const Eigen::FullPivLU<SmallMatrix> lu(reduced);
    if (!lu.isInvertible()) return std::nullopt;
    const SmallVector reducedStep = -lu.solve(reducedResidual);
    if (!reducedStep.allFinite()) return std::nullopt;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < size; ++k) {
      step[unknownIndex[k]] = reducedStep[static_cast<Eigen::Index>(k)];
    }
    unknowns += step;
    if (unknowns.x() < uLow || unknowns.x() > uHigh || unknowns.y() < 0.0 || unknowns.y() > 1.0 ||
        unknowns.z() < 0.0 || unknowns.z() > 1.0) {
      return std::nullopt;
    }
    if (step.cwiseAbs().maxCoeff() <= 1e-15) return unknowns;
  }
  return std::nullopt;
}

// One item: its upper bound and, unless the bound from its end feet already settles it given
// `lowerBound` (the best squared value known before this level), the exact value at its centre,
// and, unless the bound shows the item cannot beat `lowerBound`, the Newton solutions of cases 3
// and 4 inside it.
ItemOutcome processItem(const Problem& problem, const WorkItem& item, double lowerBound) {
  const CurveProjector::Segment& fromSegment =
      problem.from.segments()[static_cast<std::size_t>(item.segment)];
  const BezierCurve piece = pieceOf(fromSegment, item.start, item.end);
  ItemOutcome outcome;
  outcome.upperBound = std::min(item.parentBound, interpolationBound(problem, item, piece));
  const double lower = std::sqrt(std::max(0.0, lowerBound));
  if (outcome.upperBound <= (lower + problem.tolerance) * (lower + problem.tolerance)) {
    return outcome;  // eliminated or settled without a projection
  }
  outcome.center =
      sampleAt(problem, item.segment, 0.5 * (item.start + item.end), item.candidates, item.hint);
  const NearestPoint& nearest = outcome.center.nearest;
  outcome.upperBound = std::min(outcome.upperBound, centerBound(problem, piece, nearest));
  if (outcome.upperBound <= lowerBound) return outcome;

  const CurveProjector::Segment& target =
      problem.to.segments()[static_cast<std::size_t>(nearest.location.segment)];
  if (const auto solution = solveOrthogonal(piece, target, nearest.location.segmentParameter)) {
    const double local = item.start + solution->first * (item.end - item.start);
    outcome.orthogonal = sampleAt(problem, item.segment, local, item.candidates,
                                  SegmentPoint{nearest.location.segment, solution->second});
  }

  // Case 4: when the feet of the item's ends lie apart (the nearest-point map jumps inside the
  // item), the maximum may be a bisector point: Newton's method from the two feet.
  const NearestPoint startFoot =
      problem.to.pointAt(item.startFoot, fromSegment.curve.evaluate(item.start));
  const NearestPoint endFoot =
      problem.to.pointAt(item.endFoot, fromSegment.curve.evaluate(item.end));
  const double chord = (piece.evaluate(1.0) - piece.evaluate(0.0)).norm();
  if ((startFoot.point - endFoot.point).norm() > 4.0 * chord + problem.tolerance) {
    const auto& targets = problem.to.segments();
    const auto solution = solveBisector(
        fromSegment, targets[static_cast<std::size_t>(item.startFoot.segment)],
        targets[static_cast<std::size_t>(item.endFoot.segment)], 0.5 * (item.start + item.end),
        item.startFoot.segmentParameter, item.endFoot.segmentParameter, item.start, item.end);
    if (solution) {
      outcome.bisector =
          sampleAt(problem, item.segment, solution->x(), item.candidates, item.startFoot);
    }
  }
  return outcome;
}

// The `to` segments that can hold a nearest point for some u in the item: those whose box lies
// within the reach of the piece, then those the tensor-product Bernstein bound of S keeps. The
// reach is the smaller of the item's upper bound of max d^2 and (d(centre) + radius)^2, where
// the radius bounds |from(u) - from(centre)| over the item (the control points' farthest from
// the centre): d is 1-Lipschitz, so d(u) <= d(centre) + radius. Without a list yet, the segments
// are found through `to`'s box tree; when more than kMaxExplicitCandidates are near, the item
// keeps searching the whole tree (null list), so a large piece costs O(log n) per query rather
// than a scan of the whole curve, and the work follows the pieces the pruning cannot separate.
constexpr std::size_t kMaxExplicitCandidates = 64;

CandidateList filterCandidates(const Problem& problem, const WorkItem& item, double bound,
                               const Sample& center) {
  // Filtering pays only for longer lists; a short one is pruned cheaply inside nearest().
  if (item.candidates && item.candidates->size() <= 2) return item.candidates;
  const CurveProjector::Segment& fromSegment =
      problem.from.segments()[static_cast<std::size_t>(item.segment)];
  const BezierCurve piece = pieceOf(fromSegment, item.start, item.end);
  const Eigen::AlignedBox3d pieceBounds = piece.controlPointBounds();
  if (center.fromSegment == item.segment && center.squaredDistance >= 0.0) {
    const Eigen::Vector3d centerPoint = fromSegment.curve.evaluate(center.fromLocal);
    double radius = 0.0;
    for (int i = 0; i <= piece.degree(); ++i) {
      radius = std::max(radius, (piece.controlPoint(i) - centerPoint).norm());
    }
    const double reach = std::sqrt(center.squaredDistance) + radius;
    bound = std::min(bound, reach * reach * (1.0 + 1e-12));
  }
  std::vector<int> near;
  if (!item.candidates &&
      !problem.to.segmentsNear(pieceBounds, bound * (1.0 + 1e-12), kMaxExplicitCandidates, near)) {
    return item.candidates;  // too many to list: keep searching the tree
  }
  const std::vector<int>& listed = item.candidates ? *item.candidates : near;
  auto kept = std::make_shared<std::vector<int>>();
  const int count = static_cast<int>(listed.size());
  for (int k = 0; k < count; ++k) {
    const int index = listed[static_cast<std::size_t>(k)];
    const CurveProjector::Segment& target = problem.to.segments()[static_cast<std::size_t>(index)];
    const double boxDistance = pieceBounds.squaredExteriorDistance(problem.to.segmentBounds(index));
    if (boxDistance > bound * (1.0 + 1e-12)) continue;
    // S at a corner of the square is attained: below the bound, the segment must stay.
    const double cornerMinimum = std::min(
        {(piece.controlPoint(0) - target.curve.controlPoint(0)).squaredNorm(),
         (piece.controlPoint(0) - target.curve.controlPoint(target.curve.degree())).squaredNorm(),
         (piece.controlPoint(piece.degree()) - target.curve.controlPoint(0)).squaredNorm(),
         (piece.controlPoint(piece.degree()) - target.curve.controlPoint(target.curve.degree()))
             .squaredNorm()});
    if (cornerMinimum <= bound) {
      kept->push_back(index);
      continue;
    }
    const SquaredDistanceTensor tensor(piece, target.curve);
    if (tensor.minCoefficient() - tensor.roundingBound() > bound) continue;
    kept->push_back(index);
  }
  return kept;
}

// True when the point at `local` on `segment` is an "end point" in the sense of HausdorffCase:
// an end of an open curve, or a knot where the tangent direction jumps.
bool isCorner(const CurveProjector& curve, int segment, double local) {
  const auto& segments = curve.segments();
  const int count = static_cast<int>(segments.size());
  int before = -1;
  int after = -1;
  if (local <= 0.0) {
    after = segment;
    before = segment > 0 ? segment - 1 : (curve.isClosed() ? count - 1 : -1);
  } else if (local >= 1.0) {
    before = segment;
    after = segment + 1 < count ? segment + 1 : (curve.isClosed() ? 0 : -1);
  } else {
    return false;
  }
  if (before < 0 || after < 0) return true;  // an end of an open curve
  const Eigen::Vector3d incoming =
      segments[static_cast<std::size_t>(before)].hodograph().evaluate(1.0);
  const Eigen::Vector3d outgoing =
      segments[static_cast<std::size_t>(after)].hodograph().evaluate(0.0);
  if (incoming.norm() == 0.0 || outgoing.norm() == 0.0) return true;
  return (incoming.normalized() - outgoing.normalized()).norm() > 1e-9;
}

std::string formatBracket(double low, double high) {
  std::ostringstream text;
  text.precision(17);
  text << '[' << low << ", " << high << ']';
  return text.str();
}

/// The subdivision search of one directed distance h(from -> to) (see oneSidedHausdorff() in the
/// header), level by level: every item of a level is processed in parallel against the lower
/// bound the previous levels reached, then reduced in item order, so the result does not depend
/// on the thread count.
class OneSidedSearch {
 public:
  OneSidedSearch(const CurveProjector& from, const CurveProjector& to,
                 const HausdorffOptions& options)
      : from_(from),
        to_(to),
        options_(options),
        problem_{from, to, options.relativeTolerance * pairSize(from, to)},
        segmentCount_(static_cast<int>(from.segments().size())) {}

  OneSidedHausdorff run() {
    std::vector<WorkItem> items = initialItems();
    while (!items.empty()) items = processLevel(items);
    finish();
    return std::move(result_);
  }

 private:
  static double pairSize(const CurveProjector& from, const CurveProjector& to) {
    Eigen::AlignedBox3d both = from.bounds();
    both.extend(to.bounds());
    return both.diagonal().norm();
  }

  void consider(const Sample& sample) {
    if (sample.squaredDistance > best_.squaredDistance) best_ = sample;
  }

  /// The end-point cases, d at every knot of `from` (segment starts, plus the end of the last),
  /// and one item per knot span with the knots' feet.
  std::vector<WorkItem> initialItems() {
    const CandidateList allTargets;  // null: every segment of `to`
    std::vector<Sample> knotSamples(static_cast<std::size_t>(segmentCount_) + 1);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, segmentCount_ + 1), [&](const tbb::blocked_range<int>& range) {
          for (int k = range.begin(); k != range.end(); ++k) {
            const int segment = std::min(k, segmentCount_ - 1);
            knotSamples[static_cast<std::size_t>(k)] = sampleAt(
                problem_, segment, k < segmentCount_ ? 0.0 : 1.0, allTargets, std::nullopt);
          }
        });
    for (const Sample& sample : knotSamples) consider(sample);
    std::vector<WorkItem> items;
    for (int segment = 0; segment < segmentCount_; ++segment) {
      WorkItem item;
      item.segment = segment;
      item.hint = knotSamples[static_cast<std::size_t>(segment)].nearest.location;
      item.startFoot = item.hint;
      item.endFoot = knotSamples[static_cast<std::size_t>(segment) + 1].nearest.location;
      item.candidates = allTargets;
      items.push_back(std::move(item));
    }
    return items;
  }

  /// Processes one level of items and returns the next (empty when the search ends).
  std::vector<WorkItem> processLevel(const std::vector<WorkItem>& items) {
    std::vector<ItemOutcome> outcomes(items.size());
    const double lowerBefore = best_.squaredDistance;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, items.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          outcomes[i] = processItem(problem_, items[i], lowerBefore);
                        }
                      });
    result_.intervalsExamined += items.size();
    // Fixed-order reduction: the best lower bound of this level.
    for (const ItemOutcome& outcome : outcomes) {
      consider(outcome.center);
      consider(outcome.orthogonal);
      consider(outcome.bisector);
    }
    for (const WorkItem& item : items)
      result_.deepestLevel = std::max(result_.deepestLevel, item.depth);
    const std::vector<Sample> splitPoints = splitPointsOf(items, outcomes);
    const std::vector<std::size_t> toSplit = itemsToSplit(items, outcomes, splitPoints);
    if (result_.intervalsExamined + 2 * toSplit.size() > options_.maxIntervals) {
      for (const std::size_t i : toSplit)
        settledBound_ = std::max(settledBound_, outcomes[i].upperBound);
      stoppedByBudget_ = !toSplit.empty();
      return {};
    }
    return children(items, outcomes, splitPoints, toSplit);
  }

  /// Where to halve each item: at a bisector point found inside it (each side then follows one
  /// branch of the nearest-point map, so its bound converges quadratically), else the middle.
  static std::vector<Sample> splitPointsOf(const std::vector<WorkItem>& items,
                                           const std::vector<ItemOutcome>& outcomes) {
    std::vector<Sample> splitPoints(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) {
      const WorkItem& item = items[i];
      const double width = item.end - item.start;
      splitPoints[i] = outcomes[i].center;
      const Sample& bisector = outcomes[i].bisector;
      if (bisector.fromSegment == item.segment && bisector.fromLocal > item.start + 0.01 * width &&
          bisector.fromLocal < item.end - 0.01 * width) {
        splitPoints[i] = bisector;
      }
    }
    return splitPoints;
  }

  /// The items that neither are eliminated (cannot beat the best) nor settle within the
  /// tolerance nor stop at the depth bound, in item order; records the settled bounds.
  std::vector<std::size_t> itemsToSplit(const std::vector<WorkItem>& items,
                                        const std::vector<ItemOutcome>& outcomes,
                                        const std::vector<Sample>& splitPoints) {
    const double lower = std::sqrt(std::max(0.0, best_.squaredDistance));
    const double settleBelow = (lower + problem_.tolerance) * (lower + problem_.tolerance);
    std::vector<std::size_t> toSplit;
    for (std::size_t i = 0; i < items.size(); ++i) {
      const double bound = outcomes[i].upperBound;
      if (bound <= best_.squaredDistance) continue;  // eliminated: cannot beat the best
      if (bound <= settleBelow) {                    // settled within the tolerance
        settledBound_ = std::max(settledBound_, bound);
        continue;
      }
      const WorkItem& item = items[i];
      const double middle = splitPoints[i].fromLocal;
      if (item.depth >= options_.maxDepth || !(middle > item.start && middle < item.end)) {
        settledBound_ = std::max(settledBound_, bound);
        stoppedByDepth_ = true;
        continue;
      }
      toSplit.push_back(i);
    }
    return toSplit;
  }

  /// The two halves of every item in `toSplit`, in order, with their filtered candidates.
  std::vector<WorkItem> children(const std::vector<WorkItem>& items,
                                 const std::vector<ItemOutcome>& outcomes,
                                 const std::vector<Sample>& splitPoints,
                                 const std::vector<std::size_t>& toSplit) const {
    std::vector<WorkItem> next(2 * toSplit.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, toSplit.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k != range.end(); ++k) {
                          const WorkItem& parent = items[toSplit[k]];
                          const ItemOutcome& outcome = outcomes[toSplit[k]];
                          const CandidateList candidates = filterCandidates(
                              problem_, parent, outcome.upperBound, outcome.center);
                          const Sample& split = splitPoints[toSplit[k]];
                          const double middle = split.fromLocal;
                          for (int side = 0; side < 2; ++side) {
                            WorkItem child;
                            child.segment = parent.segment;
                            child.start = side == 0 ? parent.start : middle;
                            child.end = side == 0 ? middle : parent.end;
                            child.depth = parent.depth + 1;
                            child.parentBound = outcome.upperBound;
                            child.hint = outcome.center.nearest.location;
                            child.startFoot = side == 0 ? parent.startFoot : split.nearest.location;
                            child.endFoot = side == 0 ? split.nearest.location : parent.endFoot;
                            child.candidates = candidates;
                            next[2 * k + static_cast<std::size_t>(side)] = std::move(child);
                          }
                        }
                      });
    return next;
  }

  /// The result from the best sample and the settled bounds, with its warnings and case.
  void finish() {
    OneSidedHausdorff& result = result_;
    const CurveProjector::Segment& fromSegment =
        from_.segments()[static_cast<std::size_t>(best_.fromSegment)];
    result.fromParameter = fromSegment.interval.at(best_.fromLocal);
    result.fromPoint = fromSegment.curve.evaluate(best_.fromLocal);
    result.toParameter = best_.nearest.parameter;
    result.toPoint = best_.nearest.point;
    result.distance = (result.fromPoint - result.toPoint).norm();
    result.lowerBound = result.distance;
    result.upperBound = std::max(result.distance, std::sqrt(std::max(0.0, settledBound_)));
    result.converged = !stoppedByDepth_ && !stoppedByBudget_;
    if (stoppedByDepth_) {
      result.warnings.push_back("Hausdorff subdivision reached the depth bound " +
                                std::to_string(options_.maxDepth) +
                                " before the tolerance; certified bracket " +
                                formatBracket(result.lowerBound, result.upperBound));
    }
    if (stoppedByBudget_) {
      result.warnings.push_back("Hausdorff subdivision reached the bound of " +
                                std::to_string(options_.maxIntervals) +
                                " intervals before the tolerance; certified bracket " +
                                formatBracket(result.lowerBound, result.upperBound));
    }
    result.pairCase = pairCase();
  }

  /// Which of Chen et al.'s four cases the best pair is.
  HausdorffCase pairCase() const {
    const bool fromEnd = isCorner(from_, best_.fromSegment, best_.fromLocal);
    const bool toEnd =
        isCorner(to_, best_.nearest.location.segment, best_.nearest.location.segmentParameter);
    // An interior point of `from` with two or more nearest points is a bisector point (case 4),
    // whether those points are interior points or ends of `to`.
    std::ptrdiff_t nearestCount = 1;
    if (!fromEnd) {
      const double tie = 1e3 * problem_.tolerance + 1e-9 * result_.distance;
      const PointProjection projection = to_.project(result_.fromPoint, result_.distance + tie);
      nearestCount = std::count_if(projection.extrema.begin(), projection.extrema.end(),
                                   [&](const CurveExtremum& extremum) {
                                     return extremum.kind != ExtremumKind::Maximum &&
                                            extremum.distance <= projection.distance + tie;
                                   });
    }
    if (fromEnd && toEnd) return HausdorffCase::EndPoints;
    if (nearestCount >= 2) return HausdorffCase::Bisector;
    if (fromEnd || toEnd) return HausdorffCase::EndPointAndInterior;
    return HausdorffCase::MutuallyOrthogonal;
  }

  const CurveProjector& from_;
  const CurveProjector& to_;
  const HausdorffOptions& options_;
  const Problem problem_;
  const int segmentCount_;
  Sample best_;                       ///< the largest exact d^2 found so far (the lower bound)
  double settledBound_ = -kInfinity;  ///< largest upper bound of the items settled so far
  bool stoppedByDepth_ = false;
  bool stoppedByBudget_ = false;
  OneSidedHausdorff result_;
};

OneSidedHausdorff computeOneSided(const CurveProjector& from, const CurveProjector& to,
                                  const HausdorffOptions& options) {
  return OneSidedSearch(from, to, options).run();
}

void validate(const HausdorffOptions& options) {
  if (!(options.relativeTolerance > 0.0) || !std::isfinite(options.relativeTolerance)) {
    throw InputError("Hausdorff distance: the relative tolerance must be a positive finite number");
  }
  if (options.maxDepth < 1 || options.maxDepth > 200) {
    throw InputError("Hausdorff distance: maxDepth must be 1..200 (got " +
                     std::to_string(options.maxDepth) + ")");
  }
  if (options.maxIntervals < 1) {
    throw InputError("Hausdorff distance: maxIntervals must be at least 1");
  }
}

}  // namespace

OneSidedHausdorff oneSidedHausdorff(const BSplineCurve& from, const BSplineCurve& to,
                                    const HausdorffOptions& options) {
  validate(options);
  const CurveProjector fromProjector(from);
  const CurveProjector toProjector(to);
  return computeOneSided(fromProjector, toProjector, options);
}

HausdorffDistance hausdorffDistance(const BSplineCurve& a, const BSplineCurve& b,
                                    const HausdorffOptions& options) {
  validate(options);
  const CurveProjector projectorA(a);
  const CurveProjector projectorB(b);
  HausdorffDistance result;
  tbb::parallel_invoke([&] { result.aToB = computeOneSided(projectorA, projectorB, options); },
                       [&] { result.bToA = computeOneSided(projectorB, projectorA, options); });
  result.aToBIsLarger = result.aToB.distance >= result.bToA.distance;
  result.distance = std::max(result.aToB.distance, result.bToA.distance);
  result.lowerBound = std::max(result.aToB.lowerBound, result.bToA.lowerBound);
  result.upperBound = std::max(result.aToB.upperBound, result.bToA.upperBound);
  return result;
}

const char* hausdorffCaseName(HausdorffCase pairCase) {
  switch (pairCase) {
    case HausdorffCase::EndPoints:
      return "end points";
    case HausdorffCase::EndPointAndInterior:
      return "end point and interior point";
    case HausdorffCase::MutuallyOrthogonal:
      return "mutually orthogonal interior points";
    case HausdorffCase::Bisector:
      return "bisector (several nearest points)";
  }
  return "";
}

}  // namespace d2vdb
