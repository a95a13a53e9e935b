// Hausdorff distance between B-spline curves: the worked example of Chen et al. (2010) as taught
// in Shtain's lecture on it, a dozen curve pairs of every
// kind against the brute-force reference (1e-9 relative), degenerate inputs, the certified
// bracket, the depth and interval bounds, and thread-count independence.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/measure/CurveHausdorff.h"
#include "d2vdb/measure/PointProjection.h"
#include "measure/BruteForceReference.h"
#include "measure/MeasureTestCurves.h"

namespace {

using d2vdb::BSplineCurve;
using d2vdb::HausdorffCase;
using d2vdb::HausdorffDistance;
using d2vdb::OneSidedHausdorff;
using d2vdb::test::xy;

double pairSize(const BSplineCurve& a, const BSplineCurve& b) {
  Eigen::AlignedBox3d box = d2vdb::CurveProjector(a).bounds();
  box.extend(d2vdb::CurveProjector(b).bounds());
  return box.diagonal().norm();
}

// One direction against the brute force: value to 1e-9 relative, the certified bracket contains
// the reference and is within the tolerance, the reported pair is consistent.
void expectOneSidedMatches(const OneSidedHausdorff& result, const BSplineCurve& from,
                           const BSplineCurve& to, double size, const std::string& label) {
  SCOPED_TRACE(label);
  const d2vdb::test::BruteExtremum reference = d2vdb::test::bruteForceHausdorff(from, to);
  const double tolerance = 1e-9 * std::max(reference.value, 0.1 * size);
  EXPECT_NEAR(result.distance, reference.value, tolerance);
  EXPECT_TRUE(result.converged);
  EXPECT_TRUE(result.warnings.empty());
  // The bracket is certified up to rounding in evaluating the curves (a few ulps of the
  // coordinates, which matters far from the origin).
  double magnitude = 0.0;
  for (const BSplineCurve* curve : {&from, &to}) {
    for (const Eigen::Vector3d& point : curve->controlPoints()) {
      magnitude = std::max(magnitude, point.cwiseAbs().maxCoeff());
    }
  }
  const double rounding = 1e-12 * size + 1e-15 * magnitude;
  EXPECT_LE(result.lowerBound, reference.value + rounding)
      << "lower - reference = " << result.lowerBound - reference.value;
  EXPECT_GE(result.upperBound, reference.value - rounding)
      << "upper - reference = " << result.upperBound - reference.value;
  EXPECT_LE(result.upperBound - result.lowerBound, 1e-10 * size * (1.0 + 1e-9));
  EXPECT_EQ(result.lowerBound, result.distance);
  EXPECT_LT((from.evaluate(result.fromParameter) - result.fromPoint).norm(), 1e-12 * size);
  EXPECT_LT((to.evaluate(result.toParameter) - result.toPoint).norm(), 1e-12 * size);
  EXPECT_NEAR((result.fromPoint - result.toPoint).norm(), result.distance, 1e-12 * size);
  // toPoint is a nearest point of fromPoint.
  const double nearest = d2vdb::projectPoint(to, result.fromPoint).distance;
  EXPECT_NEAR(nearest, result.distance, 1e-12 * size);
}

HausdorffDistance expectMatchesBruteForce(const BSplineCurve& a, const BSplineCurve& b,
                                          const std::string& label) {
  const HausdorffDistance result = d2vdb::hausdorffDistance(a, b);
  const double size = pairSize(a, b);
  expectOneSidedMatches(result.aToB, a, b, size, label + " a->b");
  expectOneSidedMatches(result.bToA, b, a, size, label + " b->a");
  EXPECT_EQ(result.distance, std::max(result.aToB.distance, result.bToA.distance));
  EXPECT_EQ(result.aToBIsLarger, result.aToB.distance >= result.bToA.distance);
  EXPECT_EQ(result.upperBound, std::max(result.aToB.upperBound, result.bToA.upperBound));
  return result;
}

TEST(CurveHausdorff, SeedCubicBeziers) {
  const BSplineCurve a = d2vdb::test::seedCurveA();
  const BSplineCurve b = d2vdb::test::seedCurveB();
  const HausdorffDistance result = expectMatchesBruteForce(a, b, "lecture example");
  // The lecture's 261.9 with the pair (0.0685, 0) is h(B -> A): B's start point B(0) = (258, 481)
  // and its nearest point A(0.0685...) on A.
  EXPECT_NEAR(result.bToA.distance, 261.9, 0.05);
  EXPECT_EQ(result.bToA.fromParameter, 0.0);
  EXPECT_NEAR(result.bToA.toParameter, 0.0685, 5e-5);
  EXPECT_EQ(result.bToA.pairCase, HausdorffCase::EndPointAndInterior);
  EXPECT_FALSE(result.aToBIsLarger);
  EXPECT_EQ(result.distance, result.bToA.distance);
  // The other direction is smaller: h(A -> B) = 160.99..., from A's start.
  EXPECT_NEAR(result.aToB.distance, 160.99, 0.01);
  EXPECT_EQ(result.aToB.fromParameter, 0.0);
}

TEST(CurveHausdorff, LineAndQuadraticArc) {
  const BSplineCurve line = BSplineCurve::clamped(1, {xy(0, 0), xy(2, 0)}, 2);
  const BSplineCurve arc = BSplineCurve::clamped(2, {xy(-0.5, 0.3), xy(1, 1.5), xy(2.5, 0.2)}, 2);
  expectMatchesBruteForce(line, arc, "line/arc");
}

TEST(CurveHausdorff, MultiSpanPlanarCubicAndQuartic) {
  expectMatchesBruteForce(d2vdb::test::wavyCubic(), d2vdb::test::planarQuartic(), "cubic/quartic");
}

TEST(CurveHausdorff, SpatialQuinticAndQuadratic) {
  expectMatchesBruteForce(d2vdb::test::spatialQuintic(), d2vdb::test::spatialQuadratic(),
                          "quintic/quadratic");
}

TEST(CurveHausdorff, ClosedCurves) {
  expectMatchesBruteForce(d2vdb::test::closedCubic(), d2vdb::test::closedQuadraticBlob(),
                          "closed cubic/closed quadratic");
}

TEST(CurveHausdorff, PolylineWithCornersAndCubic) {
  expectMatchesBruteForce(d2vdb::test::zigzag(), d2vdb::test::wavyCubic(), "polyline/cubic");
}

TEST(CurveHausdorff, RepeatedKnotC0JointAndQuarticBezier) {
  const BSplineCurve quartic =
      BSplineCurve::clamped(4, {xy(0, 1), xy(1, -0.5), xy(2, 2.5), xy(3, 0), xy(4, 1)}, 2);
  expectMatchesBruteForce(d2vdb::test::cubicWithCorner(), quartic, "C0 joint/quartic");
}

TEST(CurveHausdorff, IntersectingCurves) {
  const BSplineCurve a = BSplineCurve::clamped(3, {xy(0, 0), xy(1, 3), xy(3, -1), xy(4, 2)}, 2);
  const BSplineCurve b = BSplineCurve::clamped(3, {xy(0, 2), xy(1.5, -1), xy(2.5, 3), xy(4, 0)}, 2);
  expectMatchesBruteForce(a, b, "intersecting");
}

TEST(CurveHausdorff, BisectorCaseUnderAnArch) {
  // A segment under an arch with a C0 apex: the farthest point of the segment, its middle, is
  // equidistant from both legs (case 4).
  const BSplineCurve segment = BSplineCurve::clamped(1, {xy(-1, 0), xy(1, 0)}, 2);
  const BSplineCurve arch(d2vdb::KnotVector(2, {0, 0, 0, 0.5, 0.5, 1, 1, 1}),
                          {xy(-1, 0.2), xy(-0.6, 1.4), xy(0, 2), xy(0.6, 1.4), xy(1, 0.2)}, 2);
  const HausdorffDistance result = expectMatchesBruteForce(segment, arch, "bisector");
  EXPECT_NEAR(result.aToB.fromParameter, 0.5, 1e-8);
  EXPECT_EQ(result.aToB.pairCase, HausdorffCase::Bisector);
}

TEST(CurveHausdorff, BisectorBetweenTwoEndPoints) {
  // Below the example's arch, the segment's middle (0, -3) is equidistant from the arch's two end
  // points, which are its nearest points: h = sqrt(10) at u = 1/2, case 4 with fixed feet.
  const BSplineCurve segment = BSplineCurve::clamped(1, {xy(-0.5, -3), xy(0.5, -3)}, 2);
  const HausdorffDistance result =
      expectMatchesBruteForce(segment, d2vdb::test::seedQuadratic(), "bisector of end points");
  EXPECT_NEAR(result.aToB.distance, std::sqrt(10.0), 1e-14);
  EXPECT_NEAR(result.aToB.fromParameter, 0.5, 1e-14);
  EXPECT_EQ(result.aToB.pairCase, HausdorffCase::Bisector);
  EXPECT_LT(result.aToB.upperBound - result.aToB.lowerBound, 1e-12);
}

TEST(CurveHausdorff, InteriorMutuallyOrthogonalPair) {
  // A gentle arc over a line: the farthest point is the arc's apex, above the line's interior.
  const BSplineCurve arc = BSplineCurve::clamped(2, {xy(0, 0.2), xy(1, 1.8), xy(2, 0.2)}, 2);
  const BSplineCurve line = BSplineCurve::clamped(1, {xy(-1, 0), xy(3, 0)}, 2);
  const HausdorffDistance result = expectMatchesBruteForce(arc, line, "orthogonal");
  EXPECT_EQ(result.aToB.pairCase, HausdorffCase::MutuallyOrthogonal);
  EXPECT_NEAR(result.aToB.distance, 1.0, 1e-12);  // apex (1, 1)
  EXPECT_NEAR(result.aToB.fromParameter, 0.5, 1e-9);
}

TEST(CurveHausdorff, SpatialClosedQuarticAndHelix) {
  expectMatchesBruteForce(d2vdb::test::closedSpatialQuartic(), d2vdb::test::helix(),
                          "closed quartic/helix");
}

TEST(CurveHausdorff, ZeroLengthSpan) {
  const BSplineCurve quadratic =
      BSplineCurve::clamped(2, {xy(0, 0.5), xy(1.5, -1), xy(2.5, 1.5), xy(4, -0.5)}, 2);
  expectMatchesBruteForce(d2vdb::test::cubicWithZeroLengthSpan(), quadratic, "zero-length span");
}

TEST(CurveHausdorff, VeryDifferentScales) {
  // A curve a millimetre long next to one a kilometre long, and a pair far from the origin.
  const BSplineCurve tiny = d2vdb::test::transformed(d2vdb::test::wavyCubic(), 1e-4, xy(3, 1));
  const BSplineCurve large =
      d2vdb::test::transformed(d2vdb::test::planarQuartic(), 150.0, xy(0, 0));
  expectMatchesBruteForce(tiny, large, "tiny/large");
  const Eigen::Vector3d far = xy(1e6, -2e6);
  expectMatchesBruteForce(d2vdb::test::transformed(d2vdb::test::seedCurveA(), 1.0, far),
                          d2vdb::test::transformed(d2vdb::test::seedCurveB(), 1.0, far),
                          "far from origin");
}

TEST(CurveHausdorff, IdenticalCurvesAndReversedCurveHaveDistanceZero) {
  for (const BSplineCurve& curve :
       {d2vdb::test::wavyCubic(), d2vdb::test::helix(), d2vdb::test::closedCubic(),
        d2vdb::test::cubicWithCorner(), d2vdb::test::cubicWithZeroLengthSpan()}) {
    const double size = pairSize(curve, curve);
    const HausdorffDistance same = d2vdb::hausdorffDistance(curve, curve);
    EXPECT_LE(same.distance, 1e-12 * size);
    EXPECT_LE(same.upperBound, 1e-10 * size);
    EXPECT_TRUE(same.aToB.converged && same.bToA.converged);
    if (!curve.isClosed()) {
      const HausdorffDistance backwards =
          d2vdb::hausdorffDistance(curve, d2vdb::test::reversed(curve));
      EXPECT_LE(backwards.distance, 1e-12 * size);
      EXPECT_LE(backwards.upperBound, 1e-10 * size);
    }
  }
}

TEST(CurveHausdorff, SameResultsForOneAndTwoThreads) {
  const std::vector<std::pair<BSplineCurve, BSplineCurve>> pairs = {
      {d2vdb::test::wavyCubic(), d2vdb::test::planarQuartic()},
      {d2vdb::test::closedSpatialQuartic(), d2vdb::test::helix()}};
  for (const auto& [a, b] : pairs) {
    HausdorffDistance results[2];
    for (int threads = 1; threads <= 2; ++threads) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      results[threads - 1] = d2vdb::hausdorffDistance(a, b);
    }
    for (const auto member : {&HausdorffDistance::aToB, &HausdorffDistance::bToA}) {
      const OneSidedHausdorff& one = results[0].*member;
      const OneSidedHausdorff& two = results[1].*member;
      EXPECT_EQ(one.distance, two.distance);
      EXPECT_EQ(one.lowerBound, two.lowerBound);
      EXPECT_EQ(one.upperBound, two.upperBound);
      EXPECT_EQ(one.fromParameter, two.fromParameter);
      EXPECT_EQ(one.toParameter, two.toParameter);
      EXPECT_EQ(one.intervalsExamined, two.intervalsExamined);
      EXPECT_EQ(one.pairCase, two.pairCase);
    }
  }
}

TEST(CurveHausdorff, BoundsStopWithACertifiedBracketAndAWarning) {
  const BSplineCurve a = d2vdb::test::wavyCubic();
  const BSplineCurve b = d2vdb::test::planarQuartic();
  const double reference = d2vdb::test::bruteForceHausdorff(a, b).value;
  d2vdb::HausdorffOptions shallow;
  shallow.maxDepth = 1;
  const OneSidedHausdorff depthLimited = d2vdb::oneSidedHausdorff(a, b, shallow);
  EXPECT_FALSE(depthLimited.converged);
  ASSERT_FALSE(depthLimited.warnings.empty());
  EXPECT_NE(depthLimited.warnings.front().find("depth"), std::string::npos);
  EXPECT_LE(depthLimited.lowerBound, reference + 1e-12);
  EXPECT_GE(depthLimited.upperBound, reference - 1e-12);
  EXPECT_GT(depthLimited.upperBound - depthLimited.lowerBound, 1e-10);

  d2vdb::HausdorffOptions few;
  few.maxIntervals = 5;
  const OneSidedHausdorff budgetLimited = d2vdb::oneSidedHausdorff(a, b, few);
  EXPECT_FALSE(budgetLimited.converged);
  ASSERT_FALSE(budgetLimited.warnings.empty());
  EXPECT_LE(budgetLimited.intervalsExamined, 5u);
  EXPECT_LE(budgetLimited.lowerBound, reference + 1e-12);
  EXPECT_GE(budgetLimited.upperBound, reference - 1e-12);

  // A looser tolerance still brackets the value, more cheaply.
  d2vdb::HausdorffOptions loose;
  loose.relativeTolerance = 1e-4;
  const OneSidedHausdorff coarse = d2vdb::oneSidedHausdorff(a, b, loose);
  const OneSidedHausdorff fine = d2vdb::oneSidedHausdorff(a, b);
  EXPECT_TRUE(coarse.converged);
  EXPECT_LE(coarse.lowerBound, reference + 1e-12);
  EXPECT_GE(coarse.upperBound, reference - 1e-12);
  EXPECT_LE(coarse.intervalsExamined, fine.intervalsExamined);
}

TEST(CurveHausdorff, InvalidOptionsAreRejected) {
  const BSplineCurve a = d2vdb::test::wavyCubic();
  d2vdb::HausdorffOptions options;
  options.relativeTolerance = 0.0;
  EXPECT_THROW(d2vdb::hausdorffDistance(a, a, options), d2vdb::InputError);
  options = {};
  options.relativeTolerance = std::nan("");
  EXPECT_THROW(d2vdb::oneSidedHausdorff(a, a, options), d2vdb::InputError);
  options = {};
  options.maxDepth = 0;
  EXPECT_THROW(d2vdb::oneSidedHausdorff(a, a, options), d2vdb::InputError);
  options = {};
  options.maxIntervals = 0;
  EXPECT_THROW(d2vdb::oneSidedHausdorff(a, a, options), d2vdb::InputError);
}

}  // namespace

namespace {

// A random clamped or closed curve: degree 1..5, 2D or 3D, random knots with repeated interior
// knots (C0 joints among them) for open curves.
BSplineCurve randomCurve(std::mt19937& rng) {
  std::uniform_int_distribution<int> degreeDistribution(1, 5);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int degree = degreeDistribution(rng);
  const int dimension = unit(rng) < 0.5 ? 2 : 3;
  const bool closed = unit(rng) < 0.25;
  const int count = degree + 1 + std::uniform_int_distribution<int>(0, 4)(rng);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    points.push_back({coordinate(rng), coordinate(rng), dimension == 3 ? coordinate(rng) : 0.0});
  }
  if (closed) return BSplineCurve::closed(degree, points, dimension);
  // Interior knots: sorted random values, some repeated up to the degree.
  std::vector<double> interior;
  while (static_cast<int>(interior.size()) < count - degree - 1) {
    const double knot = 0.05 + 0.9 * unit(rng);
    const int repeat = std::min<int>(std::uniform_int_distribution<int>(1, degree)(rng),
                                     count - degree - 1 - static_cast<int>(interior.size()));
    for (int r = 0; r < repeat; ++r) interior.push_back(knot);
  }
  std::sort(interior.begin(), interior.end());
  std::vector<double> knots(static_cast<std::size_t>(degree + 1), 0.0);
  knots.insert(knots.end(), interior.begin(), interior.end());
  knots.insert(knots.end(), static_cast<std::size_t>(degree + 1), 1.0);
  return BSplineCurve(d2vdb::KnotVector(degree, knots), points, dimension);
}

TEST(CurveHausdorff, RandomPairsMatchBruteForce) {
  std::mt19937 rng(424242);
  for (int pair = 0; pair < 24; ++pair) {
    const BSplineCurve a = randomCurve(rng);
    const BSplineCurve b = randomCurve(rng);
    const HausdorffDistance result = d2vdb::hausdorffDistance(a, b);
    const double size = pairSize(a, b);
    expectOneSidedMatches(result.aToB, a, b, size, "random pair " + std::to_string(pair) + " a->b");
    expectOneSidedMatches(result.bToA, b, a, size, "random pair " + std::to_string(pair) + " b->a");
  }
}

TEST(CurveHausdorff, UnclampedAndHighDegreeCurves) {
  const BSplineCurve unclamped(
      d2vdb::KnotVector::uniform(3, 7),
      {xy(0, 0), xy(1, 2), xy(2, -1), xy(3, 2.5), xy(4, -0.5), xy(5, 1.5), xy(6, 0)}, 2);
  expectMatchesBruteForce(unclamped, d2vdb::test::planarQuartic(), "unclamped");
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 12; ++i) points.push_back({0.5 * i, std::sin(1.3 * i), 0.3 * std::cos(i)});
  const BSplineCurve degreeNine = BSplineCurve::clamped(9, points, 3);
  const BSplineCurve degreeSeven =
      BSplineCurve::clamped(7, std::vector<Eigen::Vector3d>(points.rbegin() + 2, points.rend()), 3);
  expectMatchesBruteForce(degreeNine, degreeSeven, "degrees 9 and 7");
}

}  // namespace
