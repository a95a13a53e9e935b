// Point–curve projection: the worked example of engine/README.md with exact values, agreement with
// the brute-force reference on many curves and points, the extrema list, batch and threading.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/measure/PointProjection.h"
#include "measure/BruteForceReference.h"
#include "measure/MeasureTestCurves.h"

namespace {

using d2vdb::BSplineCurve;
using d2vdb::CurveProjector;
using d2vdb::ExtremumKind;
using d2vdb::PointProjection;
using d2vdb::test::xy;

TEST(PointProjection, SeedQuadraticExampleHasTheExactRootsAndDistance) {
  const BSplineCurve curve = d2vdb::test::seedQuadratic();
  // The projection polynomial's Bernstein coefficients (engine/README.md): -2, 14/3, -14/3, 2.
  const d2vdb::BezierCurve bezier = curve.toBezierSegments().front().curve;
  const d2vdb::BernsteinPolynomial condition =
      d2vdb::dot(bezier.translated(Eigen::Vector3d::Zero()), bezier.derivative());
  ASSERT_EQ(condition.degree(), 3);
  EXPECT_NEAR(condition.coefficient(0), -2.0, 1e-15);
  EXPECT_NEAR(condition.coefficient(1), 14.0 / 3.0, 1e-15);
  EXPECT_NEAR(condition.coefficient(2), -14.0 / 3.0, 1e-15);
  EXPECT_NEAR(condition.coefficient(3), 2.0, 1e-15);

  const PointProjection projection = d2vdb::projectPoint(curve, Eigen::Vector3d::Zero());
  const double rootOffset = std::sqrt(2.0) / 4.0;
  EXPECT_NEAR(projection.distance, std::sqrt(3.0) / 2.0, 1e-15);
  // Either of the two equally near points (t = 1/2 -+ sqrt(2)/4, x = -+ sqrt(2)/2).
  EXPECT_NEAR(std::abs(projection.parameter - 0.5), rootOffset, 1e-15);
  EXPECT_NEAR(std::abs(projection.point.x()), std::sqrt(2.0) / 2.0, 1e-15);
  EXPECT_NEAR(projection.point.y(), 0.5, 1e-15);

  // Extrema: the ends (distance 1, maxima), the two minima and the maximum at t = 1/2.
  ASSERT_EQ(projection.extrema.size(), 5u);
  const double parameters[] = {0.0, 0.5 - rootOffset, 0.5, 0.5 + rootOffset, 1.0};
  const ExtremumKind kinds[] = {ExtremumKind::Maximum, ExtremumKind::Minimum, ExtremumKind::Maximum,
                                ExtremumKind::Minimum, ExtremumKind::Maximum};
  const double distances[] = {1.0, std::sqrt(3.0) / 2.0, 1.0, std::sqrt(3.0) / 2.0, 1.0};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(projection.extrema[i].parameter, parameters[i], 1e-15) << i;
    EXPECT_EQ(projection.extrema[i].kind, kinds[i]) << i;
    EXPECT_NEAR(projection.extrema[i].distance, distances[i], 1e-15) << i;
    EXPECT_EQ(projection.extrema[i].atEndPoint, i == 0 || i == 4) << i;
  }
  EXPECT_NEAR(projection.extrema[1].point.x(), -std::sqrt(2.0) / 2.0, 1e-15);
  EXPECT_NEAR(projection.extrema[1].point.y(), 0.5, 1e-15);
  EXPECT_NEAR(projection.extrema[3].point.x(), std::sqrt(2.0) / 2.0, 1e-15);
  EXPECT_NEAR(projection.extrema[3].point.y(), 0.5, 1e-15);
  EXPECT_NEAR(projection.extrema[2].point.y(), 1.0, 1e-15);
}

// Every curve kind against the brute-force nearest point, for random points around the curve.
TEST(PointProjection, MatchesBruteForceOnManyCurves) {
  const std::vector<BSplineCurve> curves = {d2vdb::test::seedQuadratic(),
                                            d2vdb::test::seedCurveA(),
                                            d2vdb::test::wavyCubic(),
                                            d2vdb::test::planarQuartic(),
                                            d2vdb::test::spatialQuintic(),
                                            d2vdb::test::spatialQuadratic(),
                                            d2vdb::test::closedCubic(),
                                            d2vdb::test::closedQuadraticBlob(),
                                            d2vdb::test::zigzag(),
                                            d2vdb::test::cubicWithCorner(),
                                            d2vdb::test::closedSpatialQuartic(),
                                            d2vdb::test::helix(),
                                            d2vdb::test::cubicWithZeroLengthSpan()};
  std::mt19937 rng(20240601);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const BSplineCurve& curve = curves[c];
    const CurveProjector projector(curve);
    const d2vdb::test::BruteForceProjector brute(curve, 256);
    const Eigen::AlignedBox3d box = projector.bounds();
    const double size = box.diagonal().norm();
    std::uniform_real_distribution<double> unit(-0.25, 1.25);
    for (int k = 0; k < 40; ++k) {
      Eigen::Vector3d point;
      for (int axis = 0; axis < 3; ++axis) {
        point[axis] = box.min()[axis] + unit(rng) * (box.max()[axis] - box.min()[axis]);
      }
      if (curve.dimension() == 2 && k % 2 == 0) point.z() = 0.0;
      const PointProjection projection = projector.project(point);
      const d2vdb::test::BruteExtremum reference = brute.nearest(point);
      EXPECT_NEAR(projection.distance, reference.value,
                  1e-9 * std::max(reference.value, 1e-3 * size))
          << "curve " << c << " point " << point.transpose();
      // The reported point is on the curve at the reported parameter and at that distance.
      EXPECT_LT((curve.evaluate(projection.parameter) - projection.point).norm(), 1e-12 * size);
      EXPECT_NEAR((projection.point - point).norm(), projection.distance, 1e-12 * size);
      // nearest() agrees with project().
      const d2vdb::NearestPoint nearest = projector.nearest(point);
      EXPECT_NEAR(std::sqrt(nearest.squaredDistance), projection.distance, 1e-12 * size);
    }
  }
}

// The interior extrema are exactly the sign changes of (C - p) . C' seen by dense sampling.
TEST(PointProjection, ReportsEveryInteriorExtremum) {
  const std::vector<BSplineCurve> curves = {d2vdb::test::wavyCubic(), d2vdb::test::helix(),
                                            d2vdb::test::closedQuadraticBlob(),
                                            d2vdb::test::spatialQuintic()};
  const std::vector<Eigen::Vector3d> points = {
      xy(3, 0.5), {0.2, -0.3, 0.4}, xy(0.3, 0.1), {2.5, 0.4, 0.6}};
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const BSplineCurve& curve = curves[c];
    const PointProjection projection = d2vdb::projectPoint(curve, points[c]);
    // Dense sampling of the condition within each knot span.
    int minima = 0;
    int maxima = 0;
    const std::vector<double> breaks = curve.knots().breakpoints();
    for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
      double previous = 0.0;
      const int samples = 4000;
      for (int i = 1; i < samples; ++i) {  // interior of the span only
        const double t = breaks[s] + (breaks[s + 1] - breaks[s]) * i / samples;
        const d2vdb::CurveDerivatives d = curve.derivatives(t);
        const double value = (d.point - points[c]).dot(d.first);
        if (i > 1 && previous < 0.0 && value >= 0.0) ++minima;
        if (i > 1 && previous > 0.0 && value <= 0.0) ++maxima;
        previous = value;
      }
    }
    int reportedMinima = 0;
    int reportedMaxima = 0;
    for (const d2vdb::CurveExtremum& extremum : projection.extrema) {
      if (extremum.atEndPoint) continue;
      const bool atKnot = std::any_of(breaks.begin(), breaks.end(), [&](double b) {
        return std::abs(b - extremum.parameter) < 1e-9;
      });
      if (atKnot) continue;
      const d2vdb::CurveDerivatives d = curve.derivatives(extremum.parameter);
      EXPECT_NEAR((d.point - points[c]).dot(d.first), 0.0,
                  1e-10 * (1.0 + d.first.norm() * (d.point - points[c]).norm()));
      if (extremum.kind == ExtremumKind::Minimum) ++reportedMinima;
      if (extremum.kind == ExtremumKind::Maximum) ++reportedMaxima;
    }
    EXPECT_EQ(reportedMinima, minima) << "curve " << c;
    EXPECT_EQ(reportedMaxima, maxima) << "curve " << c;
  }
}

TEST(PointProjection, CornerAndEndExtrema) {
  // Outside the polyline's corner at (1, 1.5): the corner is the nearest point, a knot extremum.
  const BSplineCurve polyline = d2vdb::test::zigzag();
  const PointProjection projection = d2vdb::projectPoint(polyline, xy(1, 3));
  EXPECT_NEAR(projection.distance, 1.5, 1e-14);
  EXPECT_NEAR(projection.point.x(), 1.0, 1e-14);
  const auto corner = std::find_if(
      projection.extrema.begin(), projection.extrema.end(),
      [](const d2vdb::CurveExtremum& e) { return std::abs(e.point.x() - 1.0) < 1e-12; });
  ASSERT_NE(corner, projection.extrema.end());
  EXPECT_EQ(corner->kind, ExtremumKind::Minimum);
  // A point beyond the start of an open curve: the start is the nearest point.
  const PointProjection beyond = d2vdb::projectPoint(d2vdb::test::wavyCubic(), xy(-2, -1));
  EXPECT_DOUBLE_EQ(beyond.parameter, 0.0);
  EXPECT_TRUE(beyond.extrema.front().atEndPoint);
  EXPECT_EQ(beyond.extrema.front().kind, ExtremumKind::Minimum);
  // A point on the curve has distance zero.
  const BSplineCurve helix = d2vdb::test::helix();
  const Eigen::Vector3d onCurve = helix.evaluate(0.37);
  const PointProjection on = d2vdb::projectPoint(helix, onCurve);
  EXPECT_LT(on.distance, 1e-14);
  EXPECT_NEAR(on.parameter, 0.37, 1e-12);
}

TEST(PointProjection, ZeroLengthSpanAndNonFinitePoint) {
  const BSplineCurve curve = d2vdb::test::cubicWithZeroLengthSpan();
  const PointProjection projection = d2vdb::projectPoint(curve, xy(2, -1));
  EXPECT_NEAR(projection.distance, 1.0, 1e-14);
  EXPECT_NEAR(projection.point.x(), 2.0, 1e-14);
  EXPECT_THROW(d2vdb::projectPoint(curve, xy(std::nan(""), 0)), d2vdb::InputError);
  EXPECT_THROW(d2vdb::projectPoints(curve, {xy(0, 0), xy(INFINITY, 0)}), d2vdb::InputError);
}

TEST(PointProjection, BatchEqualsSinglePointsForAnyThreadCount) {
  const BSplineCurve curve = d2vdb::test::helix();
  std::vector<Eigen::Vector3d> points;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  for (int i = 0; i < 300; ++i)
    points.push_back({coordinate(rng), coordinate(rng), coordinate(rng)});
  std::vector<PointProjection> results[2];
  for (int threads = 1; threads <= 2; ++threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    results[threads - 1] = d2vdb::projectPoints(curve, points);
  }
  const CurveProjector projector(curve);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointProjection single = projector.project(points[i]);
    for (const auto& batch : results) {
      EXPECT_EQ(batch[i].parameter, single.parameter);
      EXPECT_EQ(batch[i].distance, single.distance);
      ASSERT_EQ(batch[i].extrema.size(), single.extrema.size());
      for (std::size_t k = 0; k < single.extrema.size(); ++k) {
        EXPECT_EQ(batch[i].extrema[k].parameter, single.extrema[k].parameter);
        EXPECT_EQ(batch[i].extrema[k].kind, single.extrema[k].kind);
      }
    }
  }
}

TEST(PointProjection, SearchRadiusKeepsTheNearestPoint) {
  const CurveProjector projector(d2vdb::test::wavyCubic());
  for (const Eigen::Vector3d& point : {xy(3, 0.5), xy(-1, 2), xy(5.5, 3)}) {
    const PointProjection full = projector.project(point);
    const PointProjection near = projector.project(point, 1.001 * full.distance);
    EXPECT_EQ(near.distance, full.distance);
    EXPECT_EQ(near.parameter, full.parameter);
    EXPECT_LE(near.extrema.size(), full.extrema.size());
  }
  EXPECT_THROW(projector.project(xy(0, 0), -1.0), d2vdb::InputError);
  EXPECT_THROW(projector.project(xy(0, 0), std::nan("")), d2vdb::InputError);
}

TEST(PointProjection, NearestWithCandidatesAndHint) {
  const BSplineCurve curve = d2vdb::test::wavyCubic();
  const CurveProjector projector(curve);
  const Eigen::Vector3d point = xy(2.2, 1.4);
  const d2vdb::NearestPoint all = projector.nearest(point);
  // Any hint and the full list give the same nearest point.
  const d2vdb::NearestPoint hinted =
      projector.nearest(point, {0, 1, 2, 3}, d2vdb::SegmentPoint{3, 0.7});
  EXPECT_EQ(hinted.squaredDistance, all.squaredDistance);
  // A hint alone is returned when nothing listed is closer.
  const d2vdb::NearestPoint hintOnly = projector.nearest(point, {}, all.location);
  EXPECT_EQ(hintOnly.squaredDistance, all.squaredDistance);
  EXPECT_THROW(projector.nearest(point, {}, std::nullopt), d2vdb::InputError);
}

TEST(PointProjection, SegmentsNearAreTheBoxesWithinTheRadiusInOrder) {
  // A random 300-span cubic: the tree query must list exactly what a scan of all boxes finds.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points(303);
  for (Eigen::Vector3d& p : points) p = {unit(random) * 10, unit(random), unit(random)};
  const BSplineCurve curve = BSplineCurve::clamped(3, points, 3);
  const CurveProjector projector(curve);
  const int count = static_cast<int>(projector.segments().size());
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d corner(unit(random) * 10, unit(random), unit(random));
    const Eigen::AlignedBox3d box(corner, corner + Eigen::Vector3d(0.3, 0.1, 0.1));
    const double squaredRadius = 0.05 * trial * trial;
    std::vector<int> expected;
    for (int i = 0; i < count; ++i) {
      if (projector.segmentBounds(i).squaredExteriorDistance(box) <= squaredRadius) {
        expected.push_back(i);
      }
    }
    std::vector<int> found;
    EXPECT_TRUE(projector.segmentsNear(box, squaredRadius, expected.size(), found));
    EXPECT_EQ(found, expected);
    if (!expected.empty()) {
      found.clear();
      EXPECT_FALSE(projector.segmentsNear(box, squaredRadius, expected.size() - 1, found));
    }
  }
}

}  // namespace
